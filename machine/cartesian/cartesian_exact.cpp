#include "machine/cartesian/cartesian_exact.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "cam/error.hpp"
#include "digitizer/level_crossing.hpp"

namespace polarcam {

namespace {

struct Cursor {
  int dir = 0;
  bool has = false;
  double level = 0, t = 0;         // pending crossing
  double lo = 0, flo = 0;          // bracket start and the axis value there minus the pending level
  double prev[2] = {0, 0};  // the axis's last two crossings on this sub-interval (for the starting guess)
  int nprev = 0;
};

}  // namespace

CartesianResult step_exact(const CartesianTrack& tr, double blu, const SpeedProfile& profile, StepSink* sink) {
  if (!(blu > 0.0) || !std::isfinite(blu)) throw InputError("the Cartesian resolution must be a positive length");
  CartesianResult res;
  res.closed = tr.closed();
  res.path_length_m = tr.length();
  res.duration_s = profile.time_at(tr.length());
  res.duration_ns = std::llround(res.duration_s * 1e9);
  cartesian_node(tr.max_abs_coordinate(), blu);  // range check
  check_step_budget(tr.length(), blu);

  const auto& P = tr.pieces();
  const auto& E = tr.extrema();
  int64_t node[2] = {cartesian_node(P.front().x_a, blu), cartesian_node(P.front().y_a, blu)};
  CartesianTally tally(res, sink);
  tally.start_at(node);
  int64_t last_ns = 0;
  auto emit = [&](int axis, int dir, double s) {
    int64_t ns = std::llround(profile.time_at(s) * 1e9);
    if (ns < last_ns) ns = last_ns;
    last_ns = ns;
    tally.step(axis, dir, ns);
  };

  std::vector<double> ts;
  for (const XYPiece& pc : P) {
    Cheb g[2] = {pc.X, pc.Y};
    g[0].scale(1.0 / blu);
    g[1].scale(1.0 / blu);
    const double base[2] = {pc.x_a / blu, pc.y_a / blu};
    const double end[2] = {pc.x_b / blu, pc.y_b / blu};
    ts.assign(1, -1.0);
    for (uint32_t k = pc.ext_begin; k < pc.ext_end; ++k) ts.push_back(E[k]);
    ts.push_back(1.0);
    double fprev[2] = {base[0], base[1]};
    for (size_t k = 0; k + 1 < ts.size(); ++k) {
      const double tl = ts[k], th = ts[k + 1];
      double fend[2];
      for (int a = 0; a < 2; ++a) fend[a] = (k + 2 == ts.size()) ? end[a] : base[a] + g[a](th);
      Cursor cur[2];
      auto advance = [&](int a) {
        Cursor& c = cur[a];
        c.has = false;
        if (c.dir == 0) return;
        const double level = static_cast<double>(node[a]) + (c.dir > 0 ? 0.5 : -0.5);
        if (c.dir > 0 ? !(fend[a] >= level) : !(fend[a] < level)) return;
        const double flo = c.flo - level;
        const double guess = c.nprev == 2 ? 2.0 * c.prev[0] - c.prev[1] : -2.0;  // linear extrapolation
        c.t = solve_crossing<false>(g[a], pc.S, level - base[a], c.lo, th, flo, fend[a] - level, guess).t;
        c.level = level;
        c.has = true;
      };
      for (int a = 0; a < 2; ++a) {
        cur[a].dir = fend[a] > fprev[a] ? 1 : (fend[a] < fprev[a] ? -1 : 0);
        cur[a].lo = tl;
        cur[a].flo = fprev[a];
        advance(a);
      }
      while (cur[0].has || cur[1].has) {
        const int a = (cur[0].has && (!cur[1].has || cur[0].t <= cur[1].t)) ? 0 : 1;
        Cursor& c = cur[a];
        emit(a, c.dir, pc.s0 + pc.S(c.t));  // S once a step, not in every Newton iteration
        node[a] += c.dir;
        c.lo = c.t;
        c.flo = c.level;  // the axis stands at the level it just crossed
        c.prev[1] = c.prev[0];
        c.prev[0] = c.t;
        if (c.nprev < 2) ++c.nprev;
        advance(a);
      }
      fprev[0] = fend[0];
      fprev[1] = fend[1];
    }
  }
  tally.finish();
  if (tally.node()[0] != node[0] || tally.node()[1] != node[1])
    throw std::logic_error("internal error: the Cartesian tally lost a step");
  if (res.closed && !res.returns_to_start)
    throw std::logic_error("internal error: a closed path did not return to its start node");
  return res;
}

}  // namespace polarcam
