#pragma once
// `polarcam process`: the milling cut of a job along its tool path (docs/process.md): the speed at each station
// (the constant-force schedule of a constant-force job, else the job's own profile), the feed per tooth, the mean
// and peak forces there, what binds the speed, the tool's limits, and the time.
#include <optional>
#include <string>
#include <vector>

#include "job/job.hpp"
#include "job/job_milling.hpp"

namespace polarcam {

struct ProcessPoint {
  double s = 0.0;       // m
  double t = 0.0;       // s, when the tool reaches s
  double v = 0.0;       // m/s
  process::MillingForceAt force;
  std::optional<process::FeedBinding> binding;  // a constant-force job's
};

struct ProcessRun {
  bool constant_force = false;
  process::MillingMode mode = process::MillingMode::up;
  const MillingSetup* setup = nullptr;            // the job's (lives as long as the job)
  std::optional<process::ConstantForceLimits> limits;
  std::vector<ProcessPoint> points;               // one per station of the schedule (or of the milling path)
  std::vector<process::FeedStretch> stretches;    // a constant-force job's
  double length_m = 0.0;
  double total_time_s = 0.0;
  // the largest of each force along the path, and whether it exceeds the tool's limit
  double max_mean_force_N = 0.0, max_peak_force_N = 0.0, max_tooth_force_N = 0.0, max_normal_force_N = 0.0;
  double max_feed_per_tooth_m = 0.0;
  std::vector<std::string> exceeded;              // the limits a job's speed exceeds (never for constant force)
};

// Throws InputError naming the job file when the job has no milling load.
ProcessRun run_process(const Job& job);

}  // namespace polarcam
