#include "optimize/torque_objective.hpp"

#include <algorithm>
#include <limits>

#include "cam/error.hpp"

namespace polarcam {

std::shared_ptr<const TorqueProblem> make_torque_problem(const MachineModel& machine, const DynamicsSetup& setup,
                                                         int side, AnalysisOptions options) {
  auto p = std::make_shared<TorqueProblem>();
  p->machine = machine;
  p->setup = setup;
  p->setup.machine = &p->machine;
  p->side = side;
  options.keep_series = false;
  p->options = options;
  return p;
}

TorqueValue evaluate_torques(const TorqueProblem& p, const Curve& path, const PolarTrack& track) {
  TorqueValue v;
  TorqueAnalysis a;
  try {
    a = analyze_motion(PlacedPath{&path, &track, 0.0, p.side}, p.setup, p.options);
  } catch (const OutsideCurveError& e) {
    v.why = e.what();
    return v;
  }
  v.computed = true;
  v.ratio_radial = a.radial.ratio.value;
  v.ratio_angular = a.angular.ratio.value;
  v.worst = worst_torque_ratio(a);
  v.ratio_sum = a.ratio_sum.value;
  v.balanced = a.balanced.value;
  const MachineModel& m = p.machine;
  if (m.radial.max_step_rate) v.rate_over = std::max(v.rate_over, a.radial.step_rate.value / *m.radial.max_step_rate);
  if (m.angular.max_step_rate)
    v.rate_over = std::max(v.rate_over, a.angular.step_rate.value / *m.angular.max_step_rate);
  v.go = judge(a, m, p.setup.safety_factor).go;
  return v;
}

}  // namespace polarcam
