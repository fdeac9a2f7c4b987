#pragma once
// The answer an operator checks before pressing start: GO when every torque ratio along the path stays within
// 1 / safety_factor and no motor is asked for more than its maximum step rate; otherwise NO-GO, naming the axis,
// the place, the margin and a speed at which the job would pass.
#include <functional>
#include <optional>
#include <string>

#include "machine/dynamics/torque_analysis.hpp"

namespace polarcam {

enum class Failure { none, torque, no_pullout, step_rate };
const char* to_string(Failure f);

struct AxisVerdict {
  Failure failure = Failure::none;
  double ratio = 0.0;   // max |torque ratio| along the path
  double margin = 0.0;  // limit / ratio - 1 (>= 0 within the limit; -0.2: the axis needs 25 % more pull-out)
  std::optional<double> rate_limit;  // Hz, the motor's maximum step rate
  double rate_margin = 0.0;          // rate_limit / max step rate - 1 (0 without a limit)
};

struct Verdict {
  bool go = true;
  double safety_factor = 1.0;
  double limit = 1.0;  // 1 / safety_factor
  AxisVerdict radial, angular;
  int axis = -1;  // 0 radial, 1 angular: the failing axis (the one furthest over), -1 for GO
  Failure failure = Failure::none;
  TorqueSample where;  // where the failing axis is furthest over its limit
};

// Throws InputError for a safety factor below 1 or not finite.
Verdict judge(const TorqueAnalysis& a, const MachineModel& m, double safety_factor);

// The largest factor f on the job's speed at which `passes(f)` holds, searched from f = 1 (downwards when it
// fails there, upwards to `f_max` when it passes) by geometric steps and bisection to `rel_tol`; the value
// returned passes. nullopt when nothing down to `f_min` passes. `capped` is set when f_max still passes.
struct SpeedSearch {
  std::optional<double> factor;
  bool capped = false;
  int evaluations = 0;
};
SpeedSearch max_passing_speed_factor(const std::function<bool(double)>& passes, double f_min = 1e-3,
                                     double f_max = 100.0, double rel_tol = 1e-4);
// The same searched with `quick` and confirmed with `passes` (confirmed_largest_passing): the factor returned passes
// `passes`.
SpeedSearch max_passing_speed_factor(const std::function<bool(double)>& quick,
                                     const std::function<bool(double)>& passes, double f_min = 1e-3,
                                     double f_max = 100.0, double rel_tol = 1e-4);

}  // namespace polarcam
