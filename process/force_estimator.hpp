#pragma once
// Cutting force from the feed-drive motor's current (J. Peng, "Design and Analysis of a CNC System for Machining
// and Monitoring", MASc thesis, UBC, 1989, Ch. 3; docs/monitoring.md):
//  - the velocity loop of the DC feed drive (Sec. 2.3.1, Eq. 2.5-2.10), states x = [I_a, W], inputs
//    u = [V_c, T_c], discretised exactly over the sample period T;
//  - the estimator of Sec. 3.2, Eq. 3.40: u(k-1) = H^-1 [x(k) - Phi x(k-1)], whose second row gives the cutting
//    torque T_c(k-1) = c0 I_a(k) + c1 W(k) + c2 I_a(k-1) + c3 W(k-1), and the feeding force F_c = 1058 T_c
//    (Eq. 3.38, measured lead-screw transmission);
//  - the remote force sensor of Sec. 3.3-3.4: I_a/T_c of Eq. 3.52 with the corrected alpha_2, alpha_1
//    (K_t (K_b + K_v K_I T_g H_g), as the block diagram of Eq. 3.41-3.51 gives), its magnitude (Eq. 3.64-3.66) and
//    its bandwidth.
// SI throughout: A, rad/s, N m, N, s.
#include <array>
#include <vector>

namespace polarcam::process {

// One feed drive's parameters (Peng 1989, Appendix A): names as the thesis prints them.
struct FeedDrive {
  double B = 0.09;          // N m s/rad, linearised viscous friction
  double H_g = 0.08872;     // V s/rad, tachogenerator
  double J_e = 0.0036;      // kg m^2
  double K_a = 0.0643;      // A/A, current feedback
  double K_b = 0.3;         // V s/rad, back EMF
  double K_d = 0.0781;      // V/count, D/A converter
  double K_e = 636.62;      // count/rad, encoder (4000 counts/rev, Eq. 2.15)
  double K_I = 25.5;        // A/V, current amplifier
  double K_p = 2.5;         // digital filter gain
  double K_v = 21.934;      // V/V, PWM stage
  double K_t = 0.3;         // N m/A, torque constant
  double L_a = 2e-3;        // H
  double R_a = 0.4;         // ohm
  double S_g = 0.0648;      // V/V, command preamplifier
  double T_g = 0.13183;     // V/V, tachometer gain
  double a = -0.8825;       // filter D(z) = K_p (z + a)/(z + b)
  double b = 0.0;
  double T = 1e-3;          // s, sample period of the controller and of the estimator
  double force_per_torque = 1058.0;  // N/(N m), Eq. 3.38 (F_c = 0.1058e4 T_c), the measured transmission
};

// Appendix A's drive; Sec. 3.2's experiment used B = 0.196 N m s/rad (the friction at 2500 counts/s).
FeedDrive peng1989_drive();

// Eq. 3.40's second row: T_c(k-1) = c[0] I_a(k) + c[1] W(k) + c[2] I_a(k-1) + c[3] W(k-1) (N m; A, rad/s).
// InputError when a parameter is not positive and finite (a, b excepted) or H is singular.
std::array<double, 4> torque_estimator(const FeedDrive& d);

// The feeding force F_c(k-1) = force_per_torque T_c(k-1) for k = 1 .. n-1 from the current and speed samples
// (equal lengths, at least two, sampled every d.T): n - 1 values, the first for sample 0.
std::vector<double> estimate_force(const FeedDrive& d, const std::vector<double>& current_A,
                                   const std::vector<double>& speed_rad_s);

// The steady-state relation of Eq. 3.62: T_c = K_t (I_a - I_f) with I_f the current that moves the table alone
// (2.5 A on Peng's machine, Sec. 3.4.2); the force is force_per_torque T_c.
double steady_force_from_current(const FeedDrive& d, double current_A, double table_current_A);

// I_a(s)/T_c(s) of Eq. 3.52: numerator gamma[0..2] (gamma_0 + gamma_1 s + gamma_2 s^2) and denominator
// alpha[0..4]. `as_printed` uses the printed alpha_2, alpha_1 (K_t (K_b K_I T_g H_g)) instead of the corrected
// K_t (K_b + K_v K_I T_g H_g).
struct CurrentSensor {
  std::array<double, 3> gamma{};
  std::array<double, 5> alpha{};
};
CurrentSensor current_sensor(const FeedDrive& d, bool as_printed = false);

// |I_a(j w)/T_c(j w)| (A/(N m)) at f_hz (Eq. 3.66); at 0 it is gamma_0/alpha_0 = 1/K_t (Eq. 3.57-3.58).
double current_per_torque(const CurrentSensor& s, double f_hz);

// The lowest frequency (Hz) where the magnitude falls to 1/sqrt(2) of its value at 0, to 1e-6 Hz; InputError when
// it does not within 100 kHz.
double sensor_bandwidth_hz(const CurrentSensor& s);

}  // namespace polarcam::process
