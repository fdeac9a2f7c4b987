#pragma once
// One dynamics case of a placed path: the torques along it for a motion and a load (machine/torque_analysis), the
// GO / NO-GO verdict (machine/verdict) and the largest factor on the speed at which the path passes. This is what
// `polarcam analyze` reports for a job (app/job_analysis adds the job file) and what the pole placement and the
// capacity searches of optimize/ evaluate (docs/optimum-loading.md): one model, one code path.
#include <optional>
#include <vector>

#include "cam/curve.hpp"
#include "digitizer/polar_track.hpp"
#include "digitizer/speed_profile.hpp"
#include "machine/dynamics/torque_analysis.hpp"
#include "machine/dynamics/verdict.hpp"

namespace polarcam {

// The motion as the dynamics see it: a cruise speed, with a ramp from and back to rest when `accel` is set, or a
// speed table (V at arc-length stations). Scaled as a whole by a speed factor; a ramp keeps its acceleration.
struct MotionLaw {
  double speed = 0.0;               // m/s
  std::optional<double> accel;      // m/s^2
  std::vector<SpeedStation> table;  // overrides `speed` when not empty
  SpeedProfilePtr profile(double length, double speed_factor = 1.0) const;
  // The cruise speed, or the largest speed of the table (m/s).
  double top_speed() const;
};

// A tool path in the machine frame, ready for the dynamics.
struct PlacedPath {
  const Curve* path = nullptr;        // tool-centre path, origin at the machine pole
  const PolarTrack* track = nullptr;  // its polar track
  double theta_shift = 0.0;           // rad added to the track's theta (place_on_grid); reported angles only
  int side = 1;                       // tool centre left (+1) or right (-1) of the travel
};

// Everything of a case that does not depend on where the path lies.
struct DynamicsSetup {
  const MachineModel* machine = nullptr;
  Load load;
  MotionLaw motion;
  double safety_factor = 1.0;
};

struct CaseDynamics {
  TorqueAnalysis analysis;
  Verdict verdict;
  SpeedSearch search;  // the largest factor on the speed at which the path passes (when asked for)
};

// The torques along the path with every speed multiplied by `speed_factor`. Throws OutsideCurveError when a step rate
// leaves a motor's tabulated pull-out curve.
TorqueAnalysis analyze_motion(const PlacedPath& p, const DynamicsSetup& s, const AnalysisOptions& o,
                              double speed_factor = 1.0);

// The analysis, the verdict and, with `search_speed`, the largest passing speed factor (searched at the default
// sampling, checked at the caller's; a factor beyond a tabulated pull-out curve does not pass).
CaseDynamics analyze_dynamics(const PlacedPath& p, const DynamicsSetup& s, const AnalysisOptions& o,
                              bool search_speed);

// The worst torque ratio of an analysis: max over both axes of max |ratio| (+inf where a motor has no pull-out
// torque left).
double worst_torque_ratio(const TorqueAnalysis& a);

}  // namespace polarcam
