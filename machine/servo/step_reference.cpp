#include "machine/servo/step_reference.hpp"

#include <algorithm>
#include <cmath>

#include "cam/error.hpp"
#include "digitizer/tape.hpp"

namespace polarcam::servo {

StepSampler::StepSampler(const double res[2], int64_t start_n, int64_t start_m)
    : res_{res[0], res[1]}, start_{start_n, start_m} {}

void StepSampler::begin(int64_t n, int64_t m) {
  start_[0] = n;
  start_[1] = m;
}

void StepSampler::step(int axis, int dir, int64_t t_ns) { steps_.push_back({t_ns, axis, dir}); }

Reference StepSampler::sample(double T, double hold) const {
  if (!(T > 0.0 && std::isfinite(T))) throw InputError("the sample period must be positive");
  const double last_s = steps_.empty() ? 0.0 : static_cast<double>(steps_.back().t_ns) * 1e-9;
  const double span = last_s + hold;
  if (span / T > 5e7) throw InputError("the path lasts more than 5e7 sample periods of the drives");
  const size_t n = static_cast<size_t>(std::ceil(span / T - 1e-9)) + 1;
  Reference r;
  r.T = T;
  r.quantum[0] = res_[0];
  r.quantum[1] = res_[1];
  r.q[0].resize(n);
  r.q[1].resize(n);
  int64_t node[2] = {start_[0], start_[1]};
  size_t i = 0;
  // sample k sees every step with t_ns <= k T (exactly, in integer nanoseconds when T is a whole number of them)
  const double T_ns = T * 1e9;
  for (size_t k = 0; k < n; ++k) {
    const double tk = static_cast<double>(k) * T_ns;
    while (i < steps_.size() && static_cast<double>(steps_[i].t_ns) <= tk + 1e-6) {
      node[steps_[i].axis] += steps_[i].dir;
      ++i;
    }
    r.q[0][k] = static_cast<double>(node[0]) * res_[0];
    r.q[1][k] = static_cast<double>(node[1]) * res_[1];
  }
  return r;
}

Reference reference_from_tape(const std::string& path, bool polar_drives, double T, double hold) {
  TapeReader reader(path);
  const TapeHeader& h = reader.header();
  const bool polar = h.axes == TapeAxes::polar;
  if (polar != polar_drives)
    throw InputError(std::string("a ") + (polar ? "polar" : "Cartesian") + " tape needs drives of its axes: " +
                         (polar ? "[r] and [theta]" : "[x] and [y]") + " in the drives file",
                     path);
  // a sand-table arm's tape steps the radial motor, which stands at r + coupling theta, not at the tool's radius
  if (tape_coupling_steps_per_rev(h) != 0.0)
    throw InputError("the tape is a sand-table arm's (its radial motor is coupled to the angle): the servo model "
                     "takes r and theta as its axes",
                     path);
  StepSampler s(h.res, h.start[0], h.start[1]);
  reader.on_tool_event([](const ToolEvent&) {});
  StepRecord rec;
  uint64_t ticks = 0;
  const double ns_per_tick = static_cast<double>(h.tick_ps) * 1e-3;
  while (reader.next(rec)) {
    ticks += rec.interval;
    s.step(rec.axis, rec.dir, static_cast<int64_t>(std::llround(static_cast<double>(ticks) * ns_per_tick)));
  }
  return in_file(path, [&] { return s.sample(T, hold); });
}

}  // namespace polarcam::servo
