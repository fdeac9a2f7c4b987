#pragma once
// A polarcam job: the machine grid (and dynamics), the contour, its placement, the tool, the motion and the load,
// read from a TOML job file (docs/job-format.md). Quantities are strings with units; the code works in SI. The CLI commands build
// everything from a Job, so they contain no geometry or physics of their own.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cam/curve.hpp"
#include "cam/toolpath.hpp"
#include "digitizer/digitize.hpp"
#include "digitizer/grid.hpp"
#include "digitizer/speed_profile.hpp"
#include "machine/axis_torque.hpp"
#include "machine/load.hpp"

namespace polarcam {

struct MotionSpec {
  double speed = 0.0;                    // m/s, tangential speed of the tool centre
  std::optional<double> accel;           // m/s^2: ramp from rest and back to rest
  std::vector<SpeedStation> table;       // V(s) stations (overrides speed when given)
  StepRule rule = StepRule::nearest;
  TravelSpec travel;
};

struct Job {
  std::string file;                      // the job file as given
  std::string machine_name;
  Grid grid;
  std::string contour_kind;
  CurvePtr contour;                      // in the contour's own frame (origin = contour pole O1)
  Placement placement;
  ToolSpec tool;
  MotionSpec motion;
  std::optional<MachineModel> dynamics;  // mechanics and motors, when the machine describes them (docs/dynamics.md)
  LoadSpec load;                         // [load]
  double safety_factor = 1.0;            // [limits]
  nlohmann::ordered_json provenance;     // canonical description of the job (SI values, no paths)
};

// Reads and checks a job file. Throws InputError with "FILE:LINE: key 'section.key': what is wrong".
Job load_job(const std::string& path);

// The tool-centre path in the machine frame.
ToolPathPtr make_job_path(const Job& job);
// The speed profile along a path of the given length.
SpeedProfilePtr make_job_profile(const Job& job, double length);

}  // namespace polarcam
