#pragma once
// A polarcam job: the machine grid (and dynamics), the contour, its placement, the tool, the motion and the load,
// read from a TOML job file (docs/job-format.md). Quantities are strings with units; the code works in SI. The CLI commands build
// everything from a Job, so they contain no geometry or physics of their own.
#include <nlohmann/json.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cam/curve.hpp"
#include "cam/toolpath.hpp"
#include "digitizer/digitize.hpp"
#include "digitizer/grid.hpp"
#include "digitizer/speed_profile.hpp"
#include "optimize/placement.hpp"
#include "machine/dynamics/axis_torque.hpp"
#include "machine/dynamics/load.hpp"
#include "machine/gcode/gcode.hpp"
#include "process/chatter_file.hpp"

namespace polarcam {

struct MillingSetup;  // job/job_milling.hpp

// [template]: the template digitizer's roller pair ([motion] speed_profile = "template"; docs/template-digitizer.md).
struct TemplateRollers {
  double thickness = 0.0;                // H, m: the template's thickness
  double roller_radius = 0.0;            // R_r, m: both rollers
  ToolSide side = ToolSide::outside;     // where the driven roller runs: inside/outside a closed outline, left/right
};

struct MotionSpec {
  double speed = 0.0;                    // m/s, tangential speed of the tool centre (template: V_t, on straight parts)
  std::optional<double> accel;           // m/s^2: ramp from rest and back to rest
  std::vector<SpeedStation> table;       // V(s) stations (overrides speed when given)
  // the speed a run is named by: `speed`, or the table's first station's
  double nominal_speed() const { return table.empty() ? speed : table.front().v; }
  std::optional<TemplateRollers> rollers;  // the template digitizer's speed, v = V_t v*(rho / H) (Eq. 3.3)
  // speed_profile = "time-optimal": the fastest schedule within the torque ratios 1/SF, the machine's step rates,
  // max_angular_speed and max_acceleration, from rest to rest, never above `speed` (docs/time-optimal.md)
  bool time_optimal = false;
  // speed_profile = "constant-force": the fastest feed that holds the milling load's mean force at nominal_force
  // within the tool's limits and `speed` (docs/process.md); needs [load] kind = "milling"
  bool constant_force = false;
  double nominal_force = 0.0;            // N
  std::optional<double> entry_length;    // m: the planned entry (default: the tool's radius)
  StepRule rule = StepRule::nearest;
  TravelSpec travel;
};

// [cartesian]: the Cartesian machine polarcam compares the polar one with (docs/cartesian.md). Nodes (i, j) sit at
// x = i BLU, y = j BLU in the contour's own frame; the placement does not apply to it.
struct CartesianSpec {
  double resolution = 0.0;          // m, BLU of both axes (default: the machine's radial resolution)
  double tolerance = 0.0;           // m, chord tolerance of the lines and arcs the DDA follows (default: BLU / 4)
  double interrupt_rate = 5000.0;   // Hz, the DDA control's interrupt rate (Appendix III of the Elbestawi thesis)
};

// A machine, parsed once: its name, its grid and work area (the drive train's resolutions), and, when the file
// describes them, its mechanics and motors. From a job's [machine] table (over its machine file) or from a
// machine file alone (load_machine).
struct Machine {
  std::string name;                      // [machine] name (may be empty)
  Grid grid;                             // resolutions, work area, home (docs/job-format.md)
  // The sand-table arm's radial-angular coupling (digitizer/theta_rho.hpp): the radial motor stands at
  // q = r + coupling theta; from `coupling`, the radial steps the radial motor must add per revolution of the arm
  // to keep the ball at its radius (coupling = steps dR / (2 pi)). 0 on a plain polar machine.
  double coupling = 0.0;                 // m/rad
  // The arm's top angular speed (rad/s), when given: near the centre, where a turn of the arm hardly moves the
  // ball, steps are timed so that the arm does not turn faster (docs/patterns.md, "The centre").
  std::optional<double> max_angular_speed;
  // The largest tangential acceleration of the tool (m/s^2), when given: the time-optimal schedule keeps within it.
  std::optional<double> max_acceleration;
  // Encoder counts per tape step of a captured run (`polarcam capture`, docs/capture.md): a step each time an
  // axis's quadrature count crosses a multiple of it. 1 when not given.
  int64_t counts_per_step = 1;
  // How the contours of a multi-contour job are joined: false (default) by a drawn move (a sand table cannot
  // lift its ball); true: the tool is lifted, moved at rapid_speed by a move linear in the motor coordinates
  // (r and theta, the theta-rho segment between the two points) and lowered (pen plotters, cutters).
  bool tool_lift = false;
  std::optional<double> rapid_speed;     // m/s of the tool point along a rapid move (default: the job's speed)
  // The time the tool needs to go up or down (a pen servo, a Z axis): `play` waits this long after each tool event
  // before the next step. The tape's times leave it out (tool events take no time there).
  double tool_dwell = 0.0;               // s
  std::optional<MachineModel> dynamics;  // mechanics and motors, when described (docs/dynamics.md)
  std::optional<GcodeSpec> gcode;        // the machine file's [gcode] table, when given (docs/gcode.md)
};

struct Job {
  std::string file;                      // the job file as given
  Machine machine;                       // [machine], over the machine file it names
  std::string contour_kind;
  CurvePtr contour;                      // in the contour's own frame (origin = contour pole O1)
  size_t contours = 1;                   // contours of the drawing joined into `contour` (an SVG's subpaths)
  // The contours one by one (in the contour's frame, in order), when there are several and the machine lifts its
  // tool between them (Machine::tool_lift): each is stepped as its own path, joined by rapid moves with the tool
  // up (pipeline/job_tape). `contour` then still holds them joined by drawn moves, for the commands that take
  // one path. Empty otherwise.
  std::vector<CurvePtr> parts;
  Placement placement;
  ToolSpec tool;
  MotionSpec motion;
  CartesianSpec cartesian;
  PlacementOptions optimize;             // [optimize]: options of `polarcam optimize` (not part of the provenance)
  LoadSpec load;                         // [load]
  double safety_factor = 1.0;            // [limits]
  // [process] chatter = "FILE.toml": the machine-workpiece structure and cut of the chatter analysis (the file format
  // of `polarcam chatter`, docs/chatter.md; relative to the job's folder); the operator's report draws its lobes.
  std::optional<process::ChatterProblem> chatter;
  std::string chatter_file;              // the file as resolved (messages only; not part of the provenance)
  std::shared_ptr<const MillingSetup> milling;  // [load] kind = "milling": the tool and the forces along the path
  nlohmann::ordered_json provenance;     // canonical description of the job (SI values, no paths)
};

// Reads and checks a job file. Throws InputError with "FILE:LINE: key 'section.key': what is wrong".
Job load_job(const std::string& path);

// Reads a machine file (a [machine] table, keys as in a job's [machine]): grid, work area and, when described,
// mechanics and motors; every key checked. Throws InputError naming the file, line and key.
// `prov`, when given, receives the machine's canonical description (as a job's provenance holds it).
Machine load_machine(const std::string& path, nlohmann::ordered_json* prov = nullptr);

// The tool-centre path in the machine frame.
ToolPathPtr make_job_path(const Job& job);
// The speed profile along the job's tool path (its arc length as the caller's track measured it). The template
// profile needs the path's curvature; the overload without a path refuses it, as it refuses the constant-force
// schedule (the milling forces along the job's own tool path).
SpeedProfilePtr make_job_profile(const Job& job, const ToolPath& path, double length);
SpeedProfilePtr make_job_profile(const Job& job, double length);

}  // namespace polarcam
