#pragma once
// The fastest safe speed along a path: a time-optimal, torque-limited speed schedule V(s) (docs/time-optimal.md).
// A. Fahim's thesis (1983), Ch. 6, raises one constant speed until the worst torque ratio reaches 1/SF; Sec. 8.2
// proposes modifying the timing of the control data for higher speeds and loads. This is the phase-plane method of
// J. E. Bobrow, S. Dubowsky and J. S. Gibson, "Time-optimal control of robotic manipulators along specified paths"
// (1985), and K. G. Shin and N. D. McKay (1985), on a grid in s: with x = V^2 and a_t = x'/2, each motor's torque
// (Eq. 5.15, 5.16) is, at a point, affine in a_t for a given V; its pull-out torque depends on V through the step
// rate. At each station the largest V with a feasible a_t is the velocity limit curve; a forward pass accelerates
// as hard as the limits let it, a backward pass brakes as hard, and the schedule is the smaller of the two, from
// rest to rest. V^2 is linear in s between stations (constant acceleration; make_table_speed_sq). The result is then
// checked with analyze_torques, exactly as `analyze` measures a job, and lowered locally where a check fails.
#include <optional>
#include <string>
#include <vector>

#include "digitizer/speed_profile.hpp"
#include "machine/dynamics/dynamics_case.hpp"

namespace polarcam {

struct TimeOptimalLimits {
  double safety_factor = 1.0;              // every |torque ratio| <= 1 / safety_factor
  std::optional<double> max_speed;         // m/s, tangential (the job's process speed, when it caps it)
  std::optional<double> max_acceleration;  // m/s^2, |tangential acceleration|
  std::optional<double> max_angular_speed; // rad/s, |theta'| of the arm
  int stations = 1200;                     // intervals of the grid in s
  int max_rounds = 80;                     // check-and-lower rounds before giving up
};

// What limits the speed on a stretch of the schedule.
enum class Binding {
  radial_torque,
  angular_torque,
  radial_step_rate,   // the radial drive's max_step_rate (or the end of its tabulated pull-out curve)
  angular_step_rate,  // likewise, angular
  angular_speed,      // the machine's max_angular_speed
  speed,              // the job's speed cap
  acceleration,       // the machine's max_acceleration
  rest,               // start and end at rest
};
const char* to_string(Binding b);

// How the speed changes over a stretch: limit ("steady"), by less than 1 % from end to end; accelerate, brake.
enum class Phase { limit, accelerate, brake };
const char* to_string(Phase p);

// A stretch of intervals whose binding constraint (the one closest to its limit, as value / limit at the ends of
// each interval) is the same.
struct ScheduleStretch {
  double s0 = 0.0, s1 = 0.0;  // m
  Phase phase = Phase::limit;
  Binding binding = Binding::radial_torque;
};

struct TimeOptimalSchedule {
  std::vector<SpeedStation> stations;  // V at the grid stations (V^2 linear between them)
  SpeedProfilePtr profile;             // make_table_speed_sq(stations)
  std::vector<ScheduleStretch> stretches;
  TorqueAnalysis check;                // analyze_torques along the profile, at the caller's options
  double worst_ratio = 0.0;            // max |torque ratio| of the check
  int rounds = 0;                      // check-and-lower rounds it took (1: the first schedule passed)
  double total_time() const { return profile->total_time(); }
};

// Throws InputError when the machine cannot move along the path at any speed (a torque ratio above 1/SF at rest) or
// when the checks cannot be met within max_rounds; OutsideCurveError as analyze_torques.
TimeOptimalSchedule time_optimal_speed(const PlacedPath& p, const MachineModel& m, const Load& load,
                                       const TimeOptimalLimits& lim, const AnalysisOptions& check = {});

// Whether a profile meets the limits as analyze_torques measures them, to `tol` (ratios <= 1/SF + tol, step rates
// and angular speed within tol relative). `excess` receives the largest value / limit found.
bool schedule_within_limits(const TorqueAnalysis& a, const MachineModel& m, const TimeOptimalLimits& lim, double tol,
                            double* excess = nullptr);

}  // namespace polarcam
