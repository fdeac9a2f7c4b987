#pragma once
// The process load on the carriage (Sec. 5.5 of A. Fahim's thesis (1983)): mass added to the carriage, and a force
// the process exerts on the tool, in path coordinates:
//  - tangential: against the direction of travel (a cutting force resisting the feed is positive);
//  - normal: perpendicular to the path, pushing the tool away from the material, i.e. towards the side the tool
//    centre lies on (a grinding wheel pushed off the work is positive).
// Grinding (Eq. 5.22-5.23): a force F_c = K_c V_t inclined at alpha_c = atan(c1) to the surface, so
// F_t = F_c cos alpha_c and F_n = F_c sin alpha_c = c1 F_t, with K_c = k_c sqrt(1 + c1^2) d w / V_tool.
// Milling: the mean force of an end mill's tooth-slice model along the path (process/milling_path.hpp,
// docs/process.md); the job layer binds the model to the job's path.
#include <functional>
#include <string>

namespace polarcam {

struct ToolForce {
  double tangential = 0.0;  // N, resisting the motion
  double normal = 0.0;      // N, pushing the tool away from the material
};

enum class LoadKind { none, inertial, grinding, force, milling };
const char* to_string(LoadKind k);

struct GrindingSpec {
  double k_c = 0.0;          // N/m^2, wheel-workpiece force factor
  double c1 = 0.0;           // normal-to-tangential force ratio
  double depth = 0.0;        // m, depth of cut d
  double width = 0.0;        // m, width of cut w
  double wheel_speed = 0.0;  // m/s, peripheral speed of the wheel V_tool
  double K_c() const;        // N s/m, Eq. 5.23: F_c = K_c V_t
  void validate() const;     // throws InputError
};

// An end mill's cut ([load] kind = "milling"): what the job gives, and the force model bound to its path.
struct MillingLoadSpec {
  std::string tool_file;        // the tool file, as resolved against the job's folder
  double spindle_speed = 0.0;   // rad/s
  double axial_depth = 0.0;     // m, b
  double radial_width = 0.0;    // m, a: the stock beyond the contour
  double K_t = 0.0;             // N/m^2, tangential specific cutting force
  double K_r = 0.0;             // N/m^2, radial
  double K_a = 0.0;             // N/m^2, axial (0 when not given)
  bool clockwise = true;        // the spindle's direction seen from the spindle (M03)
  // The mean tool force at arc length s (m) and speed V (m/s): tangential = against the travel, normal = off the
  // material. Set by the job layer (job/job_milling.hpp); make_load refuses a milling load without it.
  std::function<ToolForce(double s, double V)> model;
};

// What a job says about its load; turned into a Load for the dynamics.
struct LoadSpec {
  LoadKind kind = LoadKind::none;
  double mass = 0.0;      // kg added to the carriage (inertial; optional for the others)
  GrindingSpec grinding;  // kind grinding
  ToolForce force;        // kind force: a constant tool force
  MillingLoadSpec milling;  // kind milling
};

struct Load {
  double added_mass = 0.0;    // kg
  ToolForce force_const;      // N
  ToolForce force_per_speed;  // N s/m: the part of the force proportional to the tangential speed
  // Optional process model (the machining-process models feed this): force at arc length s (m) and speed V (m/s);
  // replaces the linear form above when set.
  std::function<ToolForce(double s, double V)> force_at;

  ToolForce force(double s, double V) const {
    if (force_at) return force_at(s, V);
    return {force_const.tangential + force_per_speed.tangential * V, force_const.normal + force_per_speed.normal * V};
  }
};

Load make_load(const LoadSpec& spec);  // validates; throws InputError

}  // namespace polarcam
