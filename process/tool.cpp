#include "process/tool.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "cam/error.hpp"

namespace polarcam::process {
namespace {

void positive(double v, const char* key, const char* what) {
  if (!(std::isfinite(v) && v > 0.0)) throw InputError(std::string("must be a positive ") + what, key);
}

}  // namespace

void check_tool(const Tool& t) {
  positive(t.diameter_m, "tool.diameter", "length, e.g. \"12.7 mm\"");
  positive(t.length_m, "tool.length", "length (the overhang from the holder), e.g. \"44.5 mm\"");
  if (t.teeth < 1 || t.teeth > 100) throw InputError("must be a whole number from 1 to 100", "tool.teeth");
  if (!(std::isfinite(t.helix_angle_rad) && t.helix_angle_rad >= 0.0 && t.helix_angle_rad < std::numbers::pi / 2))
    throw InputError("must be an angle from 0 to below 90 deg", "tool.helix_angle");
  positive(t.breaking_stress_Pa, "tool.breaking_stress", "stress, e.g. \"1500 MPa\"");
  positive(t.youngs_modulus_Pa, "tool.youngs_modulus", "modulus, e.g. \"207 GPa\"");
  if (t.yield_strength_Pa) positive(*t.yield_strength_Pa, "tool.yield_strength", "stress, e.g. \"1500 MPa\"");
  if (!(std::isfinite(t.safety_factor) && t.safety_factor >= 1.0 && t.safety_factor <= 100.0))
    throw InputError("must be a number from 1 to 100", "tool.safety_factor");
  if (t.deflection_tolerance_m)
    positive(*t.deflection_tolerance_m, "tool.deflection_tolerance", "length, e.g. \"0.01 mm\"");
  if (t.tooth) {
    positive(t.tooth->thickness_m, "tooth.thickness", "length");
    positive(t.tooth->width_m, "tooth.width", "length");
    positive(t.tooth->length_m, "tooth.length", "length");
  }
  if (t.cut) {
    if (!t.tooth) throw InputError("needs a [tooth] table (thickness, width, length) for the feed-per-tooth limit", "cut");
    positive(t.cut->spindle_speed_rad_s, "cut.spindle_speed", "speed, e.g. \"2000 rpm\"");
    positive(t.cut->axial_depth_m, "cut.axial_depth", "length");
    positive(t.cut->radial_depth_m, "cut.radial_depth", "length");
    positive(t.cut->material_constant, "cut.material_constant", "number in hp/(in^3/min), e.g. 0.2 for aluminium");
    if (t.cut->axial_depth_m > t.tooth->length_m)
      throw InputError("must not exceed tooth.length (the load sits within the fluted length)", "cut.axial_depth");
  }
  if (t.structure) {
    if (!(std::isfinite(t.structure->re_g_min_m_per_N) && t.structure->re_g_min_m_per_N < 0.0))
      throw InputError("must be a negative compliance, e.g. \"-2e-8 m/N\" (the minimum of the real part)",
                       "structure.re_g_min");
    positive(t.structure->cutting_stiffness_N_per_m2, "structure.cutting_stiffness", "stress, e.g. \"2000 N/mm^2\"");
  }
}

}  // namespace polarcam::process
