#pragma once
// The analytical parametric study of Sec. 6.2-6.5 of A. Fahim's thesis (1983), corrected
// (docs/optimum-loading.md): at one point of a contour traversed at a constant speed V_t,
//  - the torque ratios of both axes as the ratio of a quartic in V_t to [L10^2 + Lc^2 V_t^2]^(1/2) - Ld V_t
//    (Eq. 6.3-6.4 inertial, 6.9-6.10 grinding), with the thesis's coefficients Lambda_8 .. Lambda_23;
//  - their sensitivities Gamma = d ratio / d V_t (Eq. 6.5-6.6, 6.11-6.12);
//  - where along the contour the largest torques occur, as the angle gamma between the radius vector and the
//    tangent: gamma_R = pi/2 for an inertial load, Eq. 6.15 (angular, inertial), Eq. 6.19 (radial, grinding),
//    Eq. 6.20 (angular, grinding), and how these move with the speed, the force factor and the mass
//    (Eq. 6.16, 6.21-6.24), and along the contour (Eq. 6.17: d gamma / d theta = kappa ds/dtheta - 1).
// Everything here is closed form; the tests check it against the numerical analysis (machine/axis_torque,
// machine/torque_analysis). Signs: kappa > 0 for a path turning left (the thesis's rho is positive turning right in
// Eq. 6.13 and 6.19, positive turning left in Eq. 6.14); the process force as in machine/dynamics/load.hpp.
#include <array>

#include "machine/dynamics/axis_torque.hpp"

namespace polarcam {

// A point of a contour as Ch. 6 parametrises it.
struct ContourPoint {
  double r = 0.0;      // m, distance from the machine pole
  double gamma = 0.0;  // rad, angle from the radius vector e_r to the tangent (counter-clockwise)
  double kappa = 0.0;  // 1/m, signed curvature (+ turning left)
};

// The load of Ch. 6: a mass on the carriage and a grinding force F_c = K_c V_t at alpha_c to the surface
// (Eq. 5.22-5.23); K_c = 0 for a purely inertial load.
struct ParametricLoad {
  double mass = 0.0;     // kg added to the carriage (M = M_c + mass)
  double K_c = 0.0;      // N s/m
  double alpha_c = 0.0;  // rad, atan(c1)
  int side = 1;          // tool centre left (+1) or right (-1) of the travel
};

// ratio(V) = (n0 + n1 V + n2 V^2 + n3 V^3 + n4 V^4) / ([L10^2 + Lc^2 V^2]^(1/2) - Ld V)
struct RatioForm {
  std::array<double, 5> n{};  // numerator coefficients, N m ohm^2 (s/m)^k
  double L10 = 0.0, Lc = 0.0, Ld = 0.0;
  double ratio(double V) const;
  double sensitivity(double V) const;  // Gamma = d ratio / dV (s/m)
};

// The thesis's coefficients, corrected (docs/optimum-loading.md lists every correction).
struct Lambdas {
  double L8 = 0, L9 = 0, L10 = 0, L11 = 0, L12 = 0;  // radial: L8 V^2 + L9 V^4 (inertia), L11, L12 denominator
  double L14 = 0, L15 = 0, L16 = 0, L17 = 0, L18 = 0;  // angular: L14 + L15 V^2 + L16 V^4, L17, L18 denominator
  double L20 = 0, L21 = 0, L22 = 0, L23 = 0;           // grinding: L20 V + L21 V^3 (radial), L22 V + L23 V^3 (angular)
};

struct RatioForms {
  Lambdas L;
  RatioForm radial, angular;
};

// Both forms at a point. Needs electrical motors on both axes and sin(gamma) != 0 (where the arm does not turn,
// static friction makes the angular torque piecewise; the numerical analysis handles that). Throws InputError.
RatioForms ratio_forms(const MachineModel& m, const ContourPoint& p, const ParametricLoad& l);

// Where the largest torques occur (Sec. 6.4), as gamma in [0, 2 pi). Each extremum of a torque's speed-dependent
// part has a twin (the radial ones at gamma + pi with the same magnitude and the opposite sign); the value returned
// is the one in [0, pi) for the radial axis, and the largest in magnitude of the stationary points for Eq. 6.15.
//   radial, inertial: |T_R| = K2 M V^2 |kappa sin gamma| is largest at gamma = pi/2 (and 3 pi/2).
double gamma_max_radial_inertial();
//   angular, inertial (Eq. 6.15): the stationary points of h(gamma) = (J_A / r + M r) kappa cos gamma -
//   J_A sin 2gamma / r^2 satisfy sin gamma = [L24 -+ (L24^2 + rho^2 / 2)^(1/2)] / rho, L24 = (M r^3 + J_A r) /
//   (8 J_A), rho = 1 / kappa; the largest |h| occurs at a twin pair gamma, pi - gamma (same magnitude, opposite
//   sign): the one with h > 0 (the torque driving +theta) is returned. Independent of the speed.
double gamma_max_angular_inertial(const Mechanics& mk, const ContourPoint& p, double added_mass);
//   radial, grinding (Eq. 6.19): tan gamma = s tan alpha_c - M V kappa / (K_c cos alpha_c); exact.
double gamma_max_radial_grinding(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V);
//   angular, grinding (Eq. 6.20): cot gamma = V (J_A / r + M r) kappa / (K_c r cos alpha_c) - s tan alpha_c, the term
//   J_A V^2 sin 2gamma / r^2 neglected as the thesis does (the force dominates it).
double gamma_max_angular_grinding(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V);

// How these locations move (rad per unit of the parameter): Eq. 6.16 (d gamma_theta / d M, inertial), 6.21 and 6.23
// (radial, grinding, d/dV and d/dK_c), 6.22 and 6.24 (angular, grinding).
double dgamma_angular_inertial_dmass(const Mechanics& mk, const ContourPoint& p, double added_mass);
double dgamma_radial_grinding_dV(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V);
double dgamma_radial_grinding_dKc(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V);
double dgamma_angular_grinding_dV(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V);
double dgamma_angular_grinding_dKc(const Mechanics& mk, const ContourPoint& p, const ParametricLoad& l, double V);
// Along the contour (Eq. 6.17): d gamma / d theta = kappa ds/dtheta - 1; so a location that moves by d gamma moves
// by d theta = d gamma / (kappa ds/dtheta - 1) (Eq. 6.18, 6.25-6.28).
double dgamma_dtheta(double kappa, double ds_dtheta);

}  // namespace polarcam
