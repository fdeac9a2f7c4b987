#include "machine/cartesian/cartesian_exact.hpp"

#include <cmath>
#include <stdexcept>

#include "cam/error.hpp"
#include "digitizer/step_walker.hpp"

namespace polarcam {

CartesianResult step_exact(const CartesianTrack& tr, double blu, const SpeedProfile& profile, StepSink* sink) {
  if (!(blu > 0.0) || !std::isfinite(blu)) throw InputError("the Cartesian resolution must be a positive length");
  CartesianResult res;
  res.closed = tr.closed();
  res.path_length_m = tr.length();
  res.duration_s = profile.time_at(tr.length());
  res.duration_ns = std::llround(res.duration_s * 1e9);
  cartesian_node(tr.max_abs_coordinate(), blu);  // range check
  check_step_budget(tr.length(), blu);

  const TrackPiece& first = tr.pieces().front();
  int64_t node[2] = {cartesian_node(first.q_a[0], blu), cartesian_node(first.q_a[1], blu)};
  CartesianTally tally(res, sink);
  tally.start_at(node);
  int64_t last_ns = 0;
  auto emit = [&](int axis, int dir, double s) {
    int64_t ns = std::llround(profile.time_at(s) * 1e9);
    if (ns < last_ns) ns = last_ns;
    last_ns = ns;
    tally.step(axis, dir, ns);
  };
  WalkGrid wg;  // nearest rule on both axes, no offset
  wg.res[0] = wg.res[1] = blu;
  // S once a step, not in every Newton iteration; guesses extrapolated linearly
  walk_steps<true, WalkStyle<false, 2>>(tr, wg, node, emit);
  tally.finish();
  if (tally.node()[0] != node[0] || tally.node()[1] != node[1])
    throw std::logic_error("internal error: the Cartesian tally lost a step");
  if (res.closed && !res.returns_to_start)
    throw std::logic_error("internal error: a closed path did not return to its start node");
  return res;
}

}  // namespace polarcam
