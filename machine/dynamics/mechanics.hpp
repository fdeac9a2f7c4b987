#pragma once
// The mechanics of a polar machine as Ch. 5 of A. Fahim's thesis (1983) models it: an arm swung
// about the pole by a motor through a worm and worm gear, a carriage driven along the arm by a second motor
// through a power screw and split nut; every part rigid, the reducers transformers with friction losses only.
// docs/dynamics.md gives the equations with units and the corrections made to the printed ones.
#include <optional>
#include <string>

namespace polarcam {

struct Mechanics {
  double carriage_mass = 0.0;        // M_c, kg: carriage and nut, screw and radial motor reflected (Eq. 5.14)
  double arm_inertia = 0.0;          // J_A, kg m^2: arm, worm gear, screw and radial motor, worm and angular
                                     // motor reflected (Eq. 5.12)
  double arm_friction_torque = 0.0;  // F_f L_A, N m: Coulomb friction torque of the arm support
  double K1 = 0.0;                   // worm factor: angular-motor torque per unit torque on the arm (Eq. 5.12)
  double K2 = 0.0;                   // m, screw factor: radial-motor torque per unit force on the carriage (Eq. 5.14)
  double k_theta = 0.0;              // angular-motor revolutions per arm revolution
  double k_R = 0.0;                  // radial-motor revolutions per metre of carriage travel

  // Throws InputError naming the first value that is not usable.
  void validate() const;
};

// A worm and worm gear, for K1 by Eq. 5.12.
struct WormGeometry {
  double worm_pitch_radius = 0.0;    // R_w, m
  double gear_pitch_radius = 0.0;    // R_g, m
  double pressure_angle = 0.0;       // zeta, rad (normal pressure angle)
  double friction = 0.0;             // mu_1, worm on gear
  std::optional<double> lead_angle;  // lambda, rad: optional, must agree (1 %) with tan lambda = R_g / (k_theta R_w)
};

// K1 = (R_w / R_g) (cos zeta sin lambda + mu_1 cos lambda) / (cos zeta cos lambda - mu_1 sin lambda), Eq. 5.12 with
// the sign of its denominator corrected, and the lead angle lambda from the reduction: tan lambda = R_g /
// (k_theta R_w). Without friction K1 = 1 / k_theta. Throws InputError when the values are not usable or the
// worm would lock (denominator <= 0).
double worm_factor(const WormGeometry& w, double k_theta);

// A power screw and nut, for K2 by Eq. 5.14.
struct ScrewGeometry {
  double lead = 0.0;                  // l, m of travel per screw revolution
  double mean_radius = 0.0;           // R_s, m
  double thread_half_angle = 0.0;     // xi, rad: half the included thread angle (Acme 14.5 deg, square 0)
  double friction = 0.0;              // mu_2, nut on screw
  std::optional<double> helix_angle;  // psi, rad: optional, must agree (1 %) with tan psi = l / (2 pi R_s)
};

// K2 = R_s (l + 2 pi R_s mu_2 sec xi_n) / (2 pi R_s - mu_2 l sec xi_n), sec xi_n = sec xi (1 - sin^2 psi
// sin^2 xi)^(1/2), tan psi = l / (2 pi R_s) (Eq. 5.14 as the torque to drive a screw against a load; the OCR
// lost the squares). Without friction K2 = l / (2 pi). Throws InputError when the values are not usable.
double screw_factor(const ScrewGeometry& s);

}  // namespace polarcam
