#pragma once
// One DC servo feed drive after J. Peng, "Design and Analysis of a CNC System for Machining and Monitoring"
// (MASc thesis, UBC, 1989), Ch. 2 (docs/feed-drives.md): the continuous velocity loop (PWM amplifier, DC motor,
// tachogenerator; Eq. 2.1-2.7) and the encoder/up-down counter (Eq. 2.16, 2.23) as three states I_a, W, X_a, held
// by a zero-order hold over the sample period T and discretised exactly with the matrix exponential (Eq. 2.9,
// 2.10, 2.25); the digital position loop: error in counts, lead-lag D(z) = K_p (z + a)/(z + b) (Eq. 2.20, 2.26-2.30),
// the DAC gain K_d; optionally the integral action of Eq. 4.107 and a Coulomb friction torque.
//
// Positions are in encoder counts, as in the thesis; SI otherwise (V, A, rad/s, N m).
#include <array>
#include <vector>

namespace polarcam::servo {

struct ServoParams {
  // velocity loop and motor (Appendix A)
  double R_a = 0.0;   // armature resistance (ohm)
  double L_a = 0.0;   // armature inductance (H)
  double K_t = 0.0;   // torque constant (N m/A)
  double K_b = 0.0;   // back-emf constant (V s/rad)
  double J_e = 0.0;   // motor and load inertia on the motor shaft (kg m^2)
  double B = 0.0;     // linearised viscous friction (N m s/rad)
  double K_a = 0.0;   // current feedback gain (A/A)
  double K_I = 0.0;   // current amplifier gain (A/V)
  double K_v = 0.0;   // PWM gain (V/V)
  double H_g = 0.0;   // tachogenerator gain (V s/rad)
  double T_g = 0.0;   // tachogenerator feedback attenuation (V/V)
  double S_g = 0.0;   // command preamplifier gain (V/V)
  // position loop
  double K_e = 0.0;   // encoder gain (counts/rad of the motor)
  double K_d = 0.0;   // DAC gain (V/count)
  double K_p = 0.0;   // filter gain
  double a = 0.0;     // filter zero: D(z) = K_p (z + a)/(z + b)
  double b = 0.0;     // filter pole
  double T = 1e-3;    // sample period (s)
  // options
  double C_I = 0.0;        // integral gain of Eq. 4.107 (1/s): V_c += K_d C_I * (sum of errors) T; 0 = none
  double coulomb = 0.0;    // Coulomb friction torque on the motor shaft (N m), against the motion; 0 = none
};

// Throws InputError (place "KEY") for a value that is missing, not finite or out of range, or for a loop that is
// unstable (an eigenvalue of G on or outside the unit circle).
void check(const ServoParams& p);

// The velocity loop W(s)/V_c(s) = K1/(s^2 + K2 s + K3) of Eq. 2.14.
struct VelocityLoop {
  double K1 = 0.0, K2 = 0.0, K3 = 0.0;
};
VelocityLoop velocity_loop(const ServoParams& p);

// The exact discrete model x(k+1) = G x(k) + Gamma u(k) of Eq. 2.31, x = (V_d, I_a, W, X_a), u = (X_r, T_c);
// with C_I > 0 a fifth state, the error sum.
struct DiscreteModel {
  std::array<std::array<double, 3>, 3> Phi{};  // e^{A_c T}
  std::array<std::array<double, 2>, 3> H{};    // int_0^T e^{A_c t} dt B_c
  std::vector<std::vector<double>> G, Gamma;   // Eq. 2.31 (4 or 5 states)
  double spectral_radius = 0.0;                // largest |eigenvalue| of G
  double settling_time = 0.0;                  // 10 time constants of the slowest mode (s)
};
DiscreteModel discretise(const ServoParams& p);

// One sample of the simulated axis.
struct ServoSample {
  double V_c = 0.0;  // velocity command (V)
  double I_a = 0.0;  // armature current (A)
  double W = 0.0;    // motor speed (rad/s)
  double X_a = 0.0;  // actual position (counts)
};

// The axis sampled at T: step(X_r(k), T_c(k)) returns the outputs at sample k (V_c(k) from the error at k) and
// advances the state to k + 1. Starts at rest at X_a = x0.
class ServoAxis {
 public:
  explicit ServoAxis(const ServoParams& p, double x0 = 0.0);
  ServoSample step(double X_r, double T_c = 0.0);
  const DiscreteModel& model() const { return m_; }

 private:
  ServoParams p_;
  DiscreteModel m_;
  double V_d_ = 0.0, I_a_ = 0.0, W_ = 0.0, X_a_ = 0.0, sum_e_ = 0.0;
};

// Runs an axis on a reference sampled at T (counts), constant cutting torque T_c; the samples, one per reference.
std::vector<ServoSample> simulate(const ServoParams& p, const std::vector<double>& X_r, double T_c = 0.0);

}  // namespace polarcam::servo

namespace polarcam::servo {

// What `polarcam servo --report-model` prints of one axis (docs/feed-drives.md).
struct ModelReport {
  VelocityLoop velocity;                 // Eq. 2.14
  double omega_n = 0.0, zeta = 0.0;      // Eq. 2.32: sqrt(K3), K2/(2 sqrt(K3))
  double K_p_prime = 0.0, a_prime = 0.0, b_prime = 0.0;  // the filter's continuous equivalent (Eq. 3.44, Tustin)
  DiscreteModel model;                   // Eq. 2.31
  double following_error_per_speed = 0.0;  // counts of error per count/s of speed: Eq. 4.85, K3/(K1 K_e K_d D(1))
  double counts_per_Nm = 0.0;            // the table's yield under a constant cutting torque, simulated to rest (Eq. 4.101)
  // |I_a/T_c| at 1/sqrt(2) of its value at rest (1/K_t): of the continuous model of Eq. 3.52/3.64 (with the
  // filter's continuous equivalent; alpha_2, alpha_1 with K_b + K_v K_I T_g H_g) and of the exact sampled model
  double current_bandwidth_Hz = 0.0, current_bandwidth_discrete_Hz = 0.0;  // 0 when not below 1/sqrt(2) to Nyquist
};
ModelReport model_report(const ServoParams& p);

}  // namespace polarcam::servo
