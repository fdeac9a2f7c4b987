#pragma once
// Job -> dynamics glue for `polarcam analyze`, `capacity`, `optimize` and `report`: builds the tool path and its
// track once, checks the work area, and analyses the torques along it for a speed and a load with the verdict and
// the fastest speed at which the job passes (machine/dynamics_case, the model optimize/ calls too).
#include <optional>

#include "io/progress.hpp"
#include "job/job.hpp"
#include "machine/dynamics/dynamics_case.hpp"
#include "machine/dynamics/time_optimal.hpp"

namespace polarcam {

// What does not change with speed or load.
struct PreparedDynamics {
  ToolPathPtr path;
  PolarTrack track;
  double theta_shift = 0.0;  // rad, from place_on_grid
  int side = 1;              // tool centre left (+1) or right (-1) of the travel
};

// Throws InputError naming the job file: no dynamics in the machine, a path outside the work area, and so on.
PreparedDynamics prepare_dynamics(const Job& job);

// One analysis: the job's speed (or `speed`, for a job with a constant speed or a ramp) and a load.
struct DynamicsCase {
  std::optional<double> speed;  // m/s, replaces the job's speed
  LoadSpec load;
};

// The time-optimal schedule of a job (docs/time-optimal.md) against the largest constant speed that passes at the
// same safety factor (the Ch. 6 way: one speed for the whole path, raised until the worst ratio reaches 1/SF).
struct SpeedPlan {
  TimeOptimalSchedule schedule;
  std::optional<double> speed_cap;       // m/s: a time-optimal job's `speed`
  std::optional<double> constant_speed;  // m/s: the largest passing constant speed; nullopt when none passes
  bool constant_capped = false;          // that speed is the cap (or 100 times the schedule's top speed)
  double constant_time = 0.0;            // s: length / constant_speed (+inf when none passes)
  double time() const { return schedule.total_time(); }
  double saving() const { return constant_time - time(); }  // s
};

// The limits of a job's schedule: its safety factor, the machine's max_acceleration and max_angular_speed (step-rate
// limits come with the motors) and, for a time-optimal job, its speed as the top speed.
TimeOptimalLimits time_optimal_limits(const Job& job);
// Throws InputError naming the job file.
SpeedPlan plan_speed(const Job& job, const PreparedDynamics& prep, const LoadSpec& load,
                     const AnalysisOptions& check = {});
// The profile `digitize` follows for a time-optimal job: the schedule of its own path and load.
SpeedProfilePtr time_optimal_job_profile(const Job& job);

struct CaseResult {
  DynamicsCase spec;
  std::optional<double> speed;  // m/s: the cruise speed (none for a speed table)
  Load load;
  TorqueAnalysis analysis;
  Verdict verdict;
  SpeedSearch search;  // the largest factor on the speed at which the job passes
  std::optional<SpeedPlan> plan;  // a time-optimal job: the schedule analysed, and the constant speed it beats
};

// The motion of the job (a constant-speed or ramp job at `speed` when given; a speed table refuses it), the load
// and the safety factor: what the dynamics need besides the path. Throws InputError naming the job file.
MotionLaw motion_law(const Job& job, std::optional<double> speed = std::nullopt);
DynamicsSetup dynamics_setup(const Job& job, const DynamicsCase& c);
PlacedPath placed_path(const PreparedDynamics& prep);

// Throws InputError (with the job file) for a bad override or a step rate outside a motor's pull-out curve.
// `progress`: 0 when the case starts, 1 when it is done (a command analysing several cases gives each its part).
CaseResult analyze_case(const Job& job, const PreparedDynamics& prep, const DynamicsCase& c, const AnalysisOptions& opt,
                        bool search_speed = true, const Progress& progress = {});

}  // namespace polarcam
