#include "process/limits.hpp"

#include <cmath>
#include <numbers>

#include "cam/error.hpp"

namespace polarcam::process {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInch = 0.0254;
constexpr double kPoundForce = 0.45359237 * 9.80665;

}  // namespace

double shank_second_moment(double d) { return kPi * d * d * d * d / 64.0; }

double breakage_force(double d, double L, double sigma_S) { return kPi * d * d * d * sigma_S / (32.0 * L); }

double cantilever_stiffness(double d, double L, double E) {
  return 3.0 * E * shank_second_moment(d) / (L * L * L);
}

double elbestawi_tool_stiffness(double d, double L, double E) {
  return kPi * d * d * d * d * E / (1.5 * 64.0 * L * L * L);
}

double rapid_feed_per_tooth(double d, double L, double sigma_S, double E) {
  // Eq. 5.32 F_C = f_t K_t / 0.3 set equal to Eq. 5.33's F_max, with Eq. 5.34's K_t.
  return 0.3 * breakage_force(d, L, sigma_S) / elbestawi_tool_stiffness(d, L, E);
}

double shank_force_limit(double D, double L, double S_y, double n) {
  const double r = L / D;
  return S_y * kPi * D * D / (16.0 * n * std::sqrt(4.0 * r * r + 1.0));
}

double deflection_force_limit(double D, double L, double E, double y_tol) {
  return y_tol * cantilever_stiffness(D, L, E);
}

double tooth_force_limit(const ToothGeometry& g, double axial_depth, double S_y, double n) {
  const double a = g.thickness_m, b = g.width_m, l = g.length_m;
  const double m = (l - axial_depth) * (3.0 * l + 1.8 * a) / (6.0 * b * l);
  return S_y * a * a * l / (6.0 * b * n * std::sqrt(1.0 + m * m));
}

double feed_per_tooth_limit(double F_tooth, double D, int teeth, const MillingCut& cut) {
  const double F_lb = F_tooth / kPoundForce;
  const double rpm = cut.spindle_speed_rad_s * 60.0 / (2.0 * kPi);
  const double V_ft_min = rpm * kPi * (D / kInch) / 12.0;          // Eq. 15 with the circumference pi D
  const double P_hp = F_lb * V_ft_min / 33000.0;                     // Eq. 14
  const double Q_in3_min = std::pow(P_hp / cut.material_constant, 4.0 / 3.0);  // Eq. 16
  const double f_in = Q_in3_min / (teeth * rpm * (cut.axial_depth_m / kInch) * (cut.radial_depth_m / kInch));  // Eq. 17
  return f_in * kInch;
}

double fussell_eq18_constant(double circumference_factor) {
  return std::pow(circumference_factor / (6.0 * 12.0 * 33000.0), 4.0 / 3.0);
}

double chatter_limit_width(double r, double re_g_min) { return -1.0 / (2.0 * r * re_g_min); }

ToolLimits tool_limits(const Tool& t) {
  check_tool(t);
  const double d = t.diameter_m, L = t.length_m, E = t.youngs_modulus_Pa, s = t.breaking_stress_Pa;
  const double S_y = t.yield_strength_Pa.value_or(s);
  ToolLimits r;
  r.second_moment_m4 = shank_second_moment(d);
  r.breakage_force_N = breakage_force(d, L, s);
  r.stiffness_N_per_m = cantilever_stiffness(d, L, E);
  r.elbestawi_stiffness_N_per_m = elbestawi_tool_stiffness(d, L, E);
  r.rapid_feed_per_tooth_m = rapid_feed_per_tooth(d, L, s, E);
  r.shank_force_limit_N = shank_force_limit(d, L, S_y, t.safety_factor);
  if (t.deflection_tolerance_m) r.deflection_force_limit_N = deflection_force_limit(d, L, E, *t.deflection_tolerance_m);
  if (t.tooth && t.cut) {
    r.tooth_force_limit_N = tooth_force_limit(*t.tooth, t.cut->axial_depth_m, S_y, t.safety_factor);
    r.feed_per_tooth_limit_m = feed_per_tooth_limit(*r.tooth_force_limit_N, d, t.teeth, *t.cut);
  }
  if (t.structure)
    r.chatter_limit_width_m = chatter_limit_width(t.structure->cutting_stiffness_N_per_m2, t.structure->re_g_min_m_per_N);
  // Numbers that pass check_tool can still be too far apart for a double (a 1e-200 m overhang).
  for (const std::optional<double>& v :
       {std::optional<double>(r.second_moment_m4), std::optional<double>(r.breakage_force_N),
        std::optional<double>(r.stiffness_N_per_m), std::optional<double>(r.rapid_feed_per_tooth_m),
        std::optional<double>(r.shank_force_limit_N), r.deflection_force_limit_N, r.tooth_force_limit_N,
        r.feed_per_tooth_limit_m, r.chatter_limit_width_m})
    if (v && !(std::isfinite(*v) && *v > 0.0))
      throw InputError("the tool's numbers give a limit that is zero or out of range: check their units", "tool");
  return r;
}

}  // namespace polarcam::process
