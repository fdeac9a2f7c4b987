#pragma once
// The axis torques of a job at any machine-pole position (docs/optimum-loading.md): the machine model and analysis
// of `polarcam analyze` (machine/dynamics_case), run on the tool path moved with the pole. Used as the balanced-torque
// objective (Sec. 6.6.2), as the torque limit of the area search, and for the Pareto front.
#include <memory>
#include <string>

#include "cam/curve.hpp"
#include "digitizer/polar_track.hpp"
#include "machine/dynamics/dynamics_case.hpp"

namespace polarcam {

// Everything of the dynamics that does not depend on the pole. Not copyable (the setup points at the machine).
struct TorqueProblem {
  MachineModel machine;
  DynamicsSetup setup;  // setup.machine == &machine
  int side = 1;         // tool centre left (+1) or right (-1) of the travel
  AnalysisOptions options;
  TorqueProblem() = default;
  TorqueProblem(const TorqueProblem&) = delete;
  TorqueProblem& operator=(const TorqueProblem&) = delete;
};

// `setup.machine` may point anywhere: the machine is copied and the copy used.
std::shared_ptr<const TorqueProblem> make_torque_problem(const MachineModel& machine, const DynamicsSetup& setup,
                                                         int side, AnalysisOptions options = search_analysis());

struct TorqueValue {
  bool computed = false;     // false: a step rate left a motor's tabulated curve (`why`)
  std::string why;
  double ratio_radial = 0.0;   // max |torque ratio| along the path, per axis
  double ratio_angular = 0.0;
  double worst = 0.0;          // the larger of the two (+inf: a motor without pull-out torque left)
  double ratio_sum = 0.0;      // max of |ratio_R| + |ratio_theta| (the normalised T_T of Eq. 6.30)
  double balanced = 0.0;       // max of the balanced objective of Sec. 6.6.2 (+inf where it is singular)
  double rate_over = 0.0;      // max over the axes of (max step rate / the motor's limit); 0 without limits
  bool go = false;             // the verdict of `analyze` with the setup's safety factor
};

// The path in the machine frame and its track (theta_shift does not matter for the values).
TorqueValue evaluate_torques(const TorqueProblem& p, const Curve& path, const PolarTrack& track);

}  // namespace polarcam
