#include "machine/dynamics/mechanics.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "cam/error.hpp"

namespace polarcam {
namespace {

void positive(double v, const char* what) {
  if (!(v > 0.0) || !std::isfinite(v)) throw InputError(std::string(what) + " must be positive");
}
std::string deg(double rad) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g deg", rad * 180.0 / std::numbers::pi);
  return b;
}

// A given angle that the other dimensions also determine: it must agree with them.
double agreeing(const std::optional<double>& given, double implied, const char* what, const char* from) {
  if (!given) return implied;
  if (!(std::abs(*given - implied) <= 0.01 * implied))
    throw InputError(std::string("the ") + what + " " + deg(*given) + " disagrees with the " + deg(implied) + " that " +
                     from + " give");
  return *given;
}

void non_negative(double v, const char* what) {
  if (!(v >= 0.0) || !std::isfinite(v)) throw InputError(std::string(what) + " must be zero or positive");
}

}  // namespace

void Mechanics::validate() const {
  non_negative(carriage_mass, "the carriage mass M_c");
  non_negative(arm_inertia, "the arm inertia J_A");
  non_negative(arm_friction_torque, "the arm-support friction torque F_f L_A");
  positive(K1, "the worm factor K1");
  positive(K2, "the screw factor K2");
  positive(k_theta, "the angular reduction k_theta");
  positive(k_R, "the radial reduction k_R");
}

double worm_factor(const WormGeometry& w, double k_theta) {
  positive(w.worm_pitch_radius, "the worm's pitch radius");
  positive(w.gear_pitch_radius, "the worm gear's pitch radius");
  positive(k_theta, "the angular reduction k_theta");
  non_negative(w.friction, "the worm's friction coefficient");
  if (!(w.pressure_angle >= 0.0 && w.pressure_angle < 0.5 * std::numbers::pi))
    throw InputError("the worm's pressure angle must be between 0 and 90 degrees");
  const double lambda =
      agreeing(w.lead_angle, std::atan(w.gear_pitch_radius / (k_theta * w.worm_pitch_radius)), "worm's lead angle",
               "the pitch radii and the reduction (tan lambda = R_g / (k_theta R_w))");
  const double cz = std::cos(w.pressure_angle), sl = std::sin(lambda), cl = std::cos(lambda);
  const double den = cz * cl - w.friction * sl;
  if (!(den > 0.0))
    throw InputError("the worm's friction coefficient is too high for its lead angle: the drive would lock (Eq. 5.12)");
  return w.worm_pitch_radius / w.gear_pitch_radius * (cz * sl + w.friction * cl) / den;
}

double screw_factor(const ScrewGeometry& s) {
  positive(s.lead, "the screw lead");
  positive(s.mean_radius, "the screw's mean thread radius");
  non_negative(s.friction, "the screw's friction coefficient");
  if (!(s.thread_half_angle >= 0.0 && s.thread_half_angle < 0.5 * std::numbers::pi))
    throw InputError("the screw's thread half-angle must be between 0 and 90 degrees");
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  const double psi = agreeing(s.helix_angle, std::atan(s.lead / (kTwoPi * s.mean_radius)), "screw's helix angle",
                              "its lead and mean radius (tan psi = l / (2 pi R_s))");
  const double sx = std::sin(s.thread_half_angle), sp = std::sin(psi);
  const double sec_n = std::sqrt(1.0 - sp * sp * sx * sx) / std::cos(s.thread_half_angle);
  const double den = kTwoPi * s.mean_radius - s.friction * s.lead * sec_n;
  if (!(den > 0.0)) throw InputError("the screw's friction coefficient is too high for its lead: Eq. 5.14 fails");
  return s.mean_radius * (s.lead + kTwoPi * s.mean_radius * s.friction * sec_n) / den;
}

}  // namespace polarcam
