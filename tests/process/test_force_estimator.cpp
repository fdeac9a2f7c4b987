// Cutting force from motor current (Peng 1989, Ch. 3): the estimator's coefficients against the reading notes'
// corrected values and against a discretisation done here by Runge-Kutta integration (not the matrix exponential
// the library uses); the estimator recovering a known torque from a drive simulated here; the current sensor's
// magnitude against the block diagram (Eq. 3.41-3.51) solved here at s = j w, its gain 1/K_t at 0 (Eq. 3.58) and
// its bandwidth of 118.9 Hz ("about 120 Hz", Sec. 3.4.4).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "cam/error.hpp"
#include "process/force_estimator.hpp"

namespace polarcam::test {
namespace tu_process_test_force_estimator {  // named: the test files compile together

using process::FeedDrive;

// Eq. 2.5-2.6 as the thesis prints them: the derivative of [I_a, W] for inputs V_c, T_c.
std::array<double, 2> deriv(const FeedDrive& d, std::array<double, 2> x, double Vc, double Tc) {
  const double dI = -(d.K_v * d.K_a + d.R_a) / d.L_a * x[0] - (d.K_b + d.K_v * d.K_I * d.T_g * d.H_g) / d.L_a * x[1] +
                    d.K_v * d.K_I * d.S_g / d.L_a * Vc;
  const double dW = d.K_t / d.J_e * x[0] - d.B / d.J_e * x[1] - Tc / d.J_e;
  return {dI, dW};
}

// x after one sample period T with V_c, T_c held, by classical Runge-Kutta in `steps` steps.
std::array<double, 2> step(const FeedDrive& d, std::array<double, 2> x, double Vc, double Tc, int steps = 4000) {
  const double h = d.T / steps;
  for (int i = 0; i < steps; ++i) {
    auto add = [](std::array<double, 2> a, std::array<double, 2> b, double s) {
      return std::array<double, 2>{a[0] + s * b[0], a[1] + s * b[1]};
    };
    const auto k1 = deriv(d, x, Vc, Tc), k2 = deriv(d, add(x, k1, h / 2), Vc, Tc),
               k3 = deriv(d, add(x, k2, h / 2), Vc, Tc), k4 = deriv(d, add(x, k3, h), Vc, Tc);
    for (int j = 0; j < 2; ++j) x[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
  }
  return x;
}

// The estimator's coefficients by the test's own route: Phi and H column by column from Runge-Kutta steps of unit
// states and inputs, H inverted by Cramer's rule.
std::array<double, 4> rk_estimator(const FeedDrive& d) {
  const auto p0 = step(d, {1, 0}, 0, 0), p1 = step(d, {0, 1}, 0, 0);  // Phi's columns
  const auto h0 = step(d, {0, 0}, 1, 0), h1 = step(d, {0, 0}, 0, 1);  // H's columns
  const double det = h0[0] * h1[1] - h1[0] * h0[1];
  const double r0 = -h0[1] / det, r1 = h0[0] / det;  // second row of H^-1
  return {r0, r1, -(r0 * p0[0] + r1 * p0[1]), -(r0 * p1[0] + r1 * p1[1])};
}

TEST(ForceEstimator, Eq340CoefficientsWithB0196) {
  FeedDrive d = process::peng1989_drive();
  d.B = 0.196;  // Sec. 3.2's experiment
  const auto c = process::torque_estimator(d);
  const auto rk = rk_estimator(d);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(c[i], rk[i], 1e-7 * (1.0 + std::abs(rk[i]))) << i;
  // the reading notes' values (4 decimals), not the printed 0.1643, -3.6405, 0.1357, 3.4026 of Sec. 3.2
  const double note[4] = {0.1739, -3.6143, 0.1261, 3.4183};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(c[i], note[i], 6e-5) << i;
  // steady state (Eq. 3.36, T_c = K_t I_a - B W): the I_a terms sum to K_t, the W terms to -B
  EXPECT_NEAR(c[0] + c[2], d.K_t, 1e-9);
  EXPECT_NEAR(c[1] + c[3], -d.B, 1e-9);
}

TEST(ForceEstimator, RecoversATorqueFromASimulatedDrive) {
  FeedDrive d = process::peng1989_drive();
  d.B = 0.196;
  // inputs held over each period (the discretisation's assumption): a ramping command and a tooth-like torque
  std::vector<double> I, W, Tc;
  std::array<double, 2> x{0, 0};
  for (int k = 0; k < 300; ++k) {
    const double t = k * d.T;
    const double Vc = 2.0 + 0.5 * std::sin(2 * std::numbers::pi * 3 * t);
    const double T = 1.2 * std::max(0.0, std::sin(2 * std::numbers::pi * 40 * t));
    I.push_back(x[0]);
    W.push_back(x[1]);
    Tc.push_back(T);
    x = step(d, x, Vc, T, 400);
  }
  const auto F = process::estimate_force(d, I, W);
  ASSERT_EQ(F.size(), I.size() - 1);
  for (size_t k = 0; k < F.size(); ++k) EXPECT_NEAR(F[k], 1058.0 * Tc[k], 1e-4 * 1058.0) << k;
  EXPECT_THROW(process::estimate_force(d, I, std::vector<double>(3)), InputError);
}

// I_a/T_c at s from the block diagram of Sec. 3.3 (Eq. 3.41-3.51, X_r = 0), solved for I_a here.
std::complex<double> diagram(const FeedDrive& d, double f_hz) {
  const std::complex<double> s(0.0, 2 * std::numbers::pi * f_hz);
  const double Kp = d.K_p * (1 - d.a) / (1 - d.b), ap = 2 / d.T * (1 + d.a) / (1 - d.a),
               bp = 2 / d.T * (1 + d.b) / (1 - d.b);
  const std::complex<double> D = Kp * d.K_d * (s + ap) / (s + bp);  // Eq. 3.44
  const std::complex<double> G = -D * d.K_e / s;                    // V_c per W (Eq. 3.42, 3.43, 3.45)
  const std::complex<double> Q = d.K_v * d.K_I * (d.S_g * G - d.H_g * d.T_g) - d.K_b;  // V_a per W (3.46-3.48)
  const std::complex<double> Zi = d.L_a * s + d.R_a + d.K_v * d.K_a;                 // (3.47, 3.49)
  // I Zi = Q W and W (J s + B) = K_t I - T_c
  return -Q / (Zi * (d.J_e * s + d.B) - d.K_t * Q);
}

TEST(ForceEstimator, CurrentSensorMatchesTheBlockDiagram) {
  const FeedDrive d = process::peng1989_drive();
  const auto s = process::current_sensor(d);
  for (double f : {0.01, 1.0, 10.0, 50.0, 118.9, 300.0, 2000.0})
    EXPECT_NEAR(process::current_per_torque(s, f), std::abs(diagram(d, f)), 1e-9 * std::abs(diagram(d, f))) << f;
  EXPECT_NEAR(process::current_per_torque(s, 0.0), 1.0 / d.K_t, 1e-12);  // Eq. 3.58: 3.33 A per N m
}

TEST(ForceEstimator, BandwidthIs118point9Hz) {
  const FeedDrive d = process::peng1989_drive();  // Appendix A, B = 0.09
  const double bw = process::sensor_bandwidth_hz(process::current_sensor(d));
  EXPECT_NEAR(bw, 118.92, 0.01);
  EXPECT_NEAR(std::abs(diagram(d, bw)), (1.0 / d.K_t) / std::sqrt(2.0), 1e-6);
  EXPECT_GT(std::abs(diagram(d, 0.99 * bw)), (1.0 / d.K_t) / std::sqrt(2.0));
  // the printed alpha_2, alpha_1 (K_t K_b K_I T_g H_g) give another sensor: about 108.7 Hz
  const double printed = process::sensor_bandwidth_hz(process::current_sensor(d, true));
  EXPECT_NEAR(printed, 108.65, 0.05);
}

TEST(ForceEstimator, RefusesABadDrive) {
  FeedDrive d = process::peng1989_drive();
  d.J_e = 0.0;
  try {
    process::torque_estimator(d);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "J_e");
  }
  d = process::peng1989_drive();
  d.a = 1.0;
  EXPECT_THROW(process::current_sensor(d), InputError);
}

TEST(ForceEstimator, SteadyForceFromCurrent) {
  // Eq. 3.62 with I_f = 2.5 A: 3.5 A is 1 A of cutting current, 0.3 N m, 317.4 N
  EXPECT_NEAR(process::steady_force_from_current(process::peng1989_drive(), 3.5, 2.5), 0.3 * 1058.0, 1e-9);
}

}  // namespace tu_process_test_force_estimator
}  // namespace polarcam::test
