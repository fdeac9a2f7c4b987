#include "machine/dynamics/verdict.hpp"

#include <cmath>
#include <limits>

#include "cam/error.hpp"

namespace polarcam {

const char* to_string(Failure f) {
  switch (f) {
    case Failure::none:
      return "none";
    case Failure::torque:
      return "torque";
    case Failure::no_pullout:
      return "no_pullout";
    case Failure::step_rate:
      return "step_rate";
  }
  return "?";
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

SpeedSearch max_passing_speed_factor(const std::function<bool(double)>& passes, double f_min, double f_max,
                                     double rel_tol) {
  SpeedSearch out;
  auto test = [&](double f) {
    ++out.evaluations;
    return passes(f);
  };
  double lo, hi;
  if (test(1.0)) {
    lo = 1.0;
    hi = 1.25;
    while (true) {
      if (hi >= f_max) {
        if (test(f_max)) {
          out.factor = f_max;
          out.capped = true;
          return out;
        }
        hi = f_max;
        break;
      }
      if (!test(hi)) break;
      lo = hi;
      hi *= 1.25;
    }
  } else {
    hi = 1.0;
    lo = 0.8;
    while (!test(lo)) {
      hi = lo;
      lo *= 0.8;
      if (lo < f_min) return out;
    }
  }
  while (hi - lo > rel_tol * lo) {
    const double mid = 0.5 * (lo + hi);
    if (test(mid))
      lo = mid;
    else
      hi = mid;
  }
  out.factor = lo;
  return out;
}

}  // namespace polarcam
