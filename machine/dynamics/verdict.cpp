#include "machine/dynamics/verdict.hpp"

#include <cmath>
#include <limits>

#include "cam/error.hpp"
#include "machine/dynamics/largest_passing.hpp"

namespace polarcam {

const char* to_string(Failure f) {
  static constexpr const char* kNames[] = {"none", "torque", "no_pullout", "step_rate"};  // in the order of the enum
  return kNames[static_cast<int>(f)];
}

namespace {

// How far over its limit an axis is, as a factor (> 1 fails), and why.
AxisVerdict axis_verdict(const AxisExtremes& e, const StepperMotor& motor, double limit, double& over) {
  AxisVerdict v;
  v.ratio = e.ratio.value;
  v.margin =
      std::isfinite(v.ratio) ? (v.ratio > 0.0 ? limit / v.ratio - 1.0 : std::numeric_limits<double>::infinity()) : -1.0;
  over = v.ratio / limit;
  if (!std::isfinite(v.ratio)) {
    v.failure = Failure::no_pullout;
  } else if (over > 1.0) {
    v.failure = Failure::torque;
  }
  v.rate_limit = motor.max_step_rate;
  if (motor.max_step_rate) {
    v.rate_margin = *motor.max_step_rate / e.step_rate.value - 1.0;
    const double rate_over = e.step_rate.value / *motor.max_step_rate;
    if (rate_over > 1.0 && v.failure == Failure::none) {
      v.failure = Failure::step_rate;
      over = rate_over;
    }
  }
  return v;
}

}  // namespace

Verdict judge(const TorqueAnalysis& a, const MachineModel& m, double safety_factor) {
  if (!(safety_factor >= 1.0) || !std::isfinite(safety_factor))
    throw InputError("the safety factor must be a number of at least 1");
  Verdict v;
  v.safety_factor = safety_factor;
  v.limit = 1.0 / safety_factor;
  double over_r = 0.0, over_t = 0.0;
  v.radial = axis_verdict(a.radial, m.radial, v.limit, over_r);
  v.angular = axis_verdict(a.angular, m.angular, v.limit, over_t);
  v.go = v.radial.failure == Failure::none && v.angular.failure == Failure::none;
  if (!v.go) {
    const bool radial_worse =
        v.angular.failure == Failure::none || (v.radial.failure != Failure::none && !(over_t > over_r));
    v.axis = radial_worse ? 0 : 1;
    const AxisVerdict& av = radial_worse ? v.radial : v.angular;
    const AxisExtremes& e = radial_worse ? a.radial : a.angular;
    v.failure = av.failure;
    v.where = av.failure == Failure::step_rate ? e.step_rate.at : e.ratio.at;
  }
  return v;
}

namespace {

// From 1 up by 1.25 x while it passes (or down by 0.8 x while it fails), then bisection to rel_tol of the bottom.
BracketSpec speed_bracket(double f_min, double f_max, double rel_tol) {
  return {1.0, f_min, f_max, [](double f) { return 1.25 * f; }, rel_tol, false, true};
}

}  // namespace

SpeedSearch max_passing_speed_factor(const std::function<bool(double)>& passes, double f_min, double f_max,
                                     double rel_tol) {
  const LargestPassing r = largest_passing(passes, speed_bracket(f_min, f_max, rel_tol));
  return SpeedSearch{r.x, r.capped, r.evaluations};
}

SpeedSearch max_passing_speed_factor(const std::function<bool(double)>& quick,
                                     const std::function<bool(double)>& passes, double f_min, double f_max,
                                     double rel_tol) {
  const LargestPassing r = confirmed_largest_passing(quick, passes, speed_bracket(f_min, f_max, rel_tol));
  return SpeedSearch{r.x, r.capped, r.evaluations};
}

}  // namespace polarcam
