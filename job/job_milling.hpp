#pragma once
// A job's milling cut ([load] kind = "milling") and its constant-force feed ([motion] speed_profile =
// "constant-force"): the tool file, the tool's limits for the job's cut, the engagement and forces along the job's
// tool path (process/milling_path.hpp), the schedule (process/constant_force.hpp) and the speed profile the
// digitizer follows (docs/process.md).
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "digitizer/speed_profile.hpp"
#include "process/constant_force.hpp"
#include "process/limits.hpp"
#include "process/milling_path.hpp"
#include "process/tool.hpp"

namespace polarcam {

struct Job;

struct MillingSetup {
  std::string tool_file;                              // as given in the job, resolved against its folder
  process::Tool tool;
  process::ToolLimits limits;                         // the tool's, the tooth and feed-per-tooth limits for this cut
  process::MillingPathSpec spec;
  std::shared_ptr<const process::MillingPath> path;   // along the job's tool path
  // The last constant-force schedule and the limits it was made for: it depends on the path's arc length and the
  // limits only, not on the placement, so the poles of a search (and the copies of the job they make) share it.
  struct ScheduleCache {
    std::mutex mutex;
    std::optional<process::ConstantForceLimits> limits;
    std::shared_ptr<const process::ConstantForceSchedule> schedule;
  };
  mutable ScheduleCache schedule_cache;
};

// For a job whose [load] kind is "milling" (load_job calls it): reads the tool file, checks that the job's [tool]
// radius is the mill's, builds the forces along the job's tool path and binds job.load.milling.model to them.
// Throws InputError naming the file and the key.
void bind_milling(Job& job);

// The limits of a constant-force job: its nominal force, its speed as the top speed, the machine's
// max_acceleration, the tool's limits, the entry.
process::ConstantForceLimits constant_force_limits(const Job& job);
// The schedule of a constant-force job (InputError naming the job file when the job is not one).
process::ConstantForceSchedule constant_force_job_schedule(const Job& job);
// The schedule as the profile the digitizer follows: V^2 linear in s between stations (make_table_speed_sq), the
// stations' s scaled to `length` (the caller's track's measure of the same path).
SpeedProfilePtr constant_force_job_profile(const Job& job, double length);

}  // namespace polarcam
