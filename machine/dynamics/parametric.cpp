#include "machine/dynamics/parametric.hpp"

#include <cmath>
#include <numbers>
#include <variant>

#include "cam/error.hpp"

namespace polarcam {
namespace {

double wrap(double g) {
  g = std::fmod(g, 2.0 * std::numbers::pi);
  return g < 0.0 ? g + 2.0 * std::numbers::pi : g;
}

const ElectricalMotor& electrical(const StepperMotor& m, const char* axis) {
  if (const auto* e = std::get_if<ElectricalMotor>(&m.model)) return *e;
  throw InputError(std::string("the closed forms of Ch. 6 need the electrical pull-out model (Eq. 5.17) on the ") +
                   axis + " axis, not a tabulated curve");
}

// h(gamma): the V^2 bracket of the angular torque (inertial part), per K1
double angular_h(const Mechanics& mk, const ContourPoint& p, double M, double g) {
  return (mk.arm_inertia / p.r + M * p.r) * p.kappa * std::cos(g) - mk.arm_inertia * std::sin(2.0 * g) / (p.r * p.r);
}

}  // namespace

double RatioForm::ratio(double V) const {
  const double num = n[0] + V * (n[1] + V * (n[2] + V * (n[3] + V * n[4])));
  return num / (std::sqrt(L10 * L10 + Lc * Lc * V * V) - Ld * V);
}

double RatioForm::sensitivity(double V) const {
  const double root = std::sqrt(L10 * L10 + Lc * Lc * V * V);
  const double den = root - Ld * V;
  const double dnum = n[1] + V * (2.0 * n[2] + V * (3.0 * n[3] + V * 4.0 * n[4]));
  const double dden = Lc * Lc * V / root - Ld;  // Eq. 6.5's d Lambda_13 / d V_t, with Lambda_11^2 (not Lambda_10^2)
  return (dnum - ratio(V) * dden) / den;
}

RatioForms ratio_forms(const MachineModel& m, const ContourPoint& p, const ParametricLoad& l) {
  const ElectricalMotor& eR = electrical(m.radial, "radial");
  const ElectricalMotor& eT = electrical(m.angular, "angular");
  const Mechanics& mk = m.mech;
  const double sg = std::sin(p.gamma), cg = std::cos(p.gamma);
  if (!(p.r > 0.0)) throw InputError("the closed forms need a point away from the pole (r > 0)");
  if (sg == 0.0)
    throw InputError("the closed forms need sin(gamma) != 0: where the arm does not turn, static friction holds it");
  const double M = mk.carriage_mass + l.mass;
  const double s = l.side >= 0 ? 1.0 : -1.0;
  RatioForms f;
  Lambdas& L = f.L;
  // electrical frequency per unit speed: omega_R = wR V, omega_theta = wT V (Eq. 5.18, 5.19 without its 2 pi)
  const double wR = 2.0 * std::numbers::pi * eR.rotor_teeth * mk.k_R * std::abs(cg);
  const double wT = eT.rotor_teeth * mk.k_theta * std::abs(sg) / p.r;

  // radial: T_R = A1 V + A2 V^2 (Eq. 6.13 with the sign of a_cr corrected); ratio = T_R (R^2 + omega^2 L^2) /
  // (c_p V_s K_T (R^2 + omega^2 L^2)^(1/2) - K_V omega R K_T / N_s)
  {
    const double R = eR.R_a, La = eR.L_a;
    const double A1 = mk.K2 * l.K_c * std::cos(p.gamma - s * l.alpha_c);
    const double A2 = -mk.K2 * M * p.kappa * sg;
    const double q = (wR * La / R) * (wR * La / R);
    L.L8 = R * R * A2;
    L.L9 = L.L8 * q;
    L.L20 = R * R * A1;
    L.L21 = L.L20 * q;
    L.L10 = pullout_coefficient(eR.energisation) * eR.supply_voltage * eR.K_T * R;
    L.L11 = L.L10 * wR * La / R;
    L.L12 = eR.K_V * R * eR.K_T * wR / eR.rotor_teeth;
    f.radial.n = {0.0, L.L20, L.L8, L.L21, L.L9};
    f.radial.L10 = L.L10;
    f.radial.Lc = L.L11;
    f.radial.Ld = L.L12;
  }
  // angular: T_theta = B0 + B1 V + B2 V^2 (Eq. 6.14 corrected)
  {
    const double R = eT.R_a, La = eT.L_a;
    const double B0 = mk.K1 * mk.arm_friction_torque * (sg > 0.0 ? 1.0 : -1.0);
    const double B1 = mk.K1 * l.K_c * p.r * std::sin(p.gamma - s * l.alpha_c);
    const double B2 = mk.K1 * angular_h(mk, p, M, p.gamma);
    const double q = (wT * La / R) * (wT * La / R);
    L.L14 = R * R * B0;
    L.L15 = R * R * B2 + L.L14 * q;
    L.L16 = R * R * B2 * q;
    L.L22 = R * R * B1;
    L.L23 = L.L22 * q;
    const double L10 = pullout_coefficient(eT.energisation) * eT.supply_voltage * eT.K_T * R;
    L.L17 = L10 * wT * La / R;
    L.L18 = eT.K_V * R * eT.K_T * wT / eT.rotor_teeth;
    f.angular.n = {L.L14, L.L22, L.L15, L.L23, L.L16};
    f.angular.L10 = L10;
    f.angular.Lc = L.L17;
    f.angular.Ld = L.L18;
  }
  return f;
}

double gamma_max_radial_inertial() { return std::numbers::pi / 2.0; }

namespace {

// The stationary points of h as sin(gamma) = L24 kappa +- (L24^2 kappa^2 + 1/2)^(1/2); the root chosen (sign +-1)
double angular_inertial(const Mechanics& mk, const ContourPoint& p, double added_mass, double* sign) {
  const double M = mk.carriage_mass + added_mass;
  const double L24 = (M * p.r * p.r * p.r + mk.arm_inertia * p.r) / (8.0 * mk.arm_inertia);
  const double b = L24 * p.kappa, root = std::sqrt(b * b + 0.5);
  double best = 0.0, best_h = -1.0;
  for (double sg : {1.0, -1.0}) {
    const double s = b + sg * root;
    if (std::abs(s) > 1.0) continue;
    for (double g : {std::asin(s), std::numbers::pi - std::asin(s)}) {
      // the two roots of one sign are twins (h(pi - gamma) = -h(gamma)): take the one where h > 0, so that the
      // choice does not depend on rounding
      const double hs = angular_h(mk, p, M, g), h = std::abs(hs);
      if (h > best_h * (1.0 + 1e-9) || (h >= best_h * (1.0 - 1e-9) && hs > 0.0)) {
        best_h = h;
        best = wrap(g);
        if (sign) *sign = sg;
      }
    }
  }
  return best;
}

double radial_u(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V) {
  const double s = l.side >= 0 ? 1.0 : -1.0, M = mk.carriage_mass + l.mass;
  return s * std::tan(l.alpha_c) - M * V * p.kappa / (l.K_c * std::cos(l.alpha_c));
}

double angular_w(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V) {
  const double s = l.side >= 0 ? 1.0 : -1.0, M = mk.carriage_mass + l.mass;
  return V * (mk.arm_inertia / p.r + M * p.r) * p.kappa / (l.K_c * p.r * std::cos(l.alpha_c)) - s * std::tan(l.alpha_c);
}

void need_force(const ParametricLoad& l) {
  if (!(l.K_c > 0.0)) throw InputError("the grinding locations (Eq. 6.19, 6.20) need a force factor K_c > 0");
}

}  // namespace

double gamma_max_angular_inertial(const Mechanics& mk, const ContourPoint& p, double added_mass) {
  return angular_inertial(mk, p, added_mass, nullptr);
}

double gamma_max_radial_grinding(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V) {
  need_force(l);
  return wrap(std::atan(radial_u(mk, p, l, V)));
}

double gamma_max_angular_grinding(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V) {
  need_force(l);
  const double w = angular_w(mk, p, l, V);
  return std::numbers::pi / 2.0 - std::atan(w);  // arccot in (0, pi)
}

double dgamma_angular_inertial_dmass(const Mechanics& mk, const ContourPoint& p, double added_mass) {
  double sign = 1.0;
  const double g = angular_inertial(mk, p, added_mass, &sign);
  const double M = mk.carriage_mass + added_mass;
  const double L24 = (M * p.r * p.r * p.r + mk.arm_inertia * p.r) / (8.0 * mk.arm_inertia);
  const double b = L24 * p.kappa, root = std::sqrt(b * b + 0.5);
  const double db = p.r * p.r * p.r / (8.0 * mk.arm_inertia) * p.kappa;
  const double ds = db * (1.0 + sign * b / root);
  return ds / std::cos(g);  // sin gamma = s: ds = cos gamma d gamma
}

double dgamma_radial_grinding_dV(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V) {
  need_force(l);
  const double u = radial_u(mk, p, l, V), M = mk.carriage_mass + l.mass;
  return -M * p.kappa / (l.K_c * std::cos(l.alpha_c)) / (1.0 + u * u);
}

double dgamma_radial_grinding_dKc(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V) {
  need_force(l);
  const double u = radial_u(mk, p, l, V), M = mk.carriage_mass + l.mass;
  return M * V * p.kappa / (l.K_c * l.K_c * std::cos(l.alpha_c)) / (1.0 + u * u);
}

double dgamma_angular_grinding_dV(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V) {
  need_force(l);
  const double w = angular_w(mk, p, l, V), M = mk.carriage_mass + l.mass;
  const double dw = (mk.arm_inertia / p.r + M * p.r) * p.kappa / (l.K_c * p.r * std::cos(l.alpha_c));
  return -dw / (1.0 + w * w);
}

double dgamma_angular_grinding_dKc(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V) {
  need_force(l);
  const double w = angular_w(mk, p, l, V), M = mk.carriage_mass + l.mass;
  const double dw = -V * (mk.arm_inertia / p.r + M * p.r) * p.kappa / (l.K_c * l.K_c * p.r * std::cos(l.alpha_c));
  return -dw / (1.0 + w * w);
}

double dgamma_dtheta(double kappa, double ds_dtheta) { return kappa * ds_dtheta - 1.0; }

}  // namespace polarcam
