// One servo axis (J. Peng 1989, Ch. 2 and Sec. 4.2): the exact discretisation against an independent numerical
// integration, the steady following error against Eq. 4.85 computed here from the parameters and against the
// thesis's printed values, the error per cutting torque (Eq. 4.101), the closed-loop poles against the corrected
// Appendix B and C, a step response that settles, linearity.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>

#include "cam/error.hpp"
#include "machine/servo/drives_file.hpp"
#include "machine/servo/servo_axis.hpp"

namespace tu_machine_servo_test_servo_axis {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::servo;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kCount = 5.08e-3 / 4000.0;  // m per count on a 5.08 mm screw (Sec. 2.3.2)

// Appendix A, typed here (not read through the library).
ServoParams appendix_a(double B = 0.09) {
  ServoParams p;
  p.R_a = 0.4;
  p.L_a = 2e-3;
  p.K_t = 0.3;
  p.K_b = 0.3;
  p.J_e = 0.0036;
  p.B = B;
  p.K_a = 0.0643;
  p.K_I = 25.5;
  p.K_v = 21.934;
  p.H_g = 0.08872;
  p.T_g = 0.13183;
  p.S_g = 0.0648;
  p.K_e = 4000.0 / (2.0 * kPi);
  p.K_d = 0.0781;
  p.K_p = 2.5;
  p.a = -0.8825;
  p.b = 0.0;
  p.T = 1e-3;
  return p;
}

// Eq. 4.85 with the analogue filter's DC gain K_p' a'/b' equal to the digital one, D(1) = K_p (1 + a)/(1 + b).
double eq_4_85_counts(const ServoParams& p, double f_counts) {
  const double K1 = p.K_t * p.S_g * p.K_I * p.K_v / (p.L_a * p.J_e);
  const double K3 = (p.B * (p.R_a + p.K_v * p.K_a) + p.K_t * (p.K_b + p.H_g * p.T_g * p.K_v * p.K_I)) / (p.J_e * p.L_a);
  const double D1 = p.K_p * (1.0 + p.a) / (1.0 + p.b);
  return f_counts * K3 / (K1 * p.K_e * p.K_d * D1);
}

// The steady error of a ramp X_r = v t after `seconds`.
double ramp_error(const ServoParams& p, double v_counts, double seconds = 2.0) {
  ServoAxis axis(p);
  const int n = static_cast<int>(seconds / p.T);
  double e = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double xr = v_counts * k * p.T;
    e = xr - axis.step(xr).X_a;
  }
  return e;
}

}  // namespace

TEST(ServoAxis, DiscretisationMatchesFineIntegration) {
  // Phi and H against RK4 on the continuous Eq. 2.24 with 10^4 substeps per sample, unit inputs held.
  const ServoParams p = appendix_a();
  const DiscreteModel m = discretise(p);
  const double A[3][3] = {{-(p.K_v * p.K_a + p.R_a) / p.L_a, -(p.K_b + p.K_v * p.K_I * p.T_g * p.H_g) / p.L_a, 0},
                          {p.K_t / p.J_e, -p.B / p.J_e, 0},
                          {0, p.K_e, 0}};
  const double Bc[3][2] = {{p.K_v * p.K_I * p.S_g / p.L_a, 0}, {0, -1.0 / p.J_e}, {0, 0}};
  auto run = [&](const double x0[3], const double u[2], double out[3]) {
    double x[3] = {x0[0], x0[1], x0[2]};
    const int N = 10000;
    const double h = p.T / N;
    auto f = [&](const double* s, double* d) {
      for (int i = 0; i < 3; ++i) d[i] = A[i][0] * s[0] + A[i][1] * s[1] + A[i][2] * s[2] + Bc[i][0] * u[0] + Bc[i][1] * u[1];
    };
    for (int k = 0; k < N; ++k) {
      double k1[3], k2[3], k3[3], k4[3], t[3];
      f(x, k1);
      for (int i = 0; i < 3; ++i) t[i] = x[i] + 0.5 * h * k1[i];
      f(t, k2);
      for (int i = 0; i < 3; ++i) t[i] = x[i] + 0.5 * h * k2[i];
      f(t, k3);
      for (int i = 0; i < 3; ++i) t[i] = x[i] + h * k3[i];
      f(t, k4);
      for (int i = 0; i < 3; ++i) x[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    }
    for (int i = 0; i < 3; ++i) out[i] = x[i];
  };
  for (int j = 0; j < 3; ++j) {
    double x0[3] = {0, 0, 0}, u[2] = {0, 0}, out[3];
    x0[j] = 1.0;
    run(x0, u, out);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.Phi[i][j], out[i], 1e-9 * (1.0 + std::abs(out[i]))) << i << j;
  }
  for (int j = 0; j < 2; ++j) {
    double x0[3] = {0, 0, 0}, u[2] = {0, 0}, out[3];
    u[j] = 1.0;
    run(x0, u, out);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.H[i][j], out[i], 1e-9 * (1.0 + std::abs(out[i]))) << i << j;
  }
  // the first row of Eq. 2.31's G and Gamma follow from the filter alone: the printed 0.1724, -0.1724
  EXPECT_NEAR(m.G[0][3], 0.1724, 1e-4);
  EXPECT_NEAR(m.Gamma[0][0], -0.1724, 1e-4);
}

TEST(ServoAxis, ClosedLoopPolesFollowCorrectedAppendixBC) {
  // Appendix B (cos(w_d T) where it prints cos(w_d)) and C (alpha_2, alpha_1 with + a b_2, + a b_1), b = 0:
  // the roots of z^4 + alpha_3 z^3 + alpha_2 z^2 + alpha_1 z + alpha_0 are the eigenvalues of G.
  for (double B : {0.09, 0.3}) {
    const ServoParams p = appendix_a(B);
    const double T = p.T, a = p.a;
    const double K1 = p.K_t * p.S_g * p.K_I * p.K_v / (p.L_a * p.J_e);
    const double K2 = B / p.J_e + (p.R_a + p.K_v * p.K_a) / p.L_a;
    const double K3 = (B * (p.R_a + p.K_v * p.K_a) + p.K_t * (p.K_b + p.H_g * p.T_g * p.K_v * p.K_I)) / (p.J_e * p.L_a);
    const double wn = std::sqrt(K3), xi = K2 / (2 * wn);
    ASSERT_LT(xi, 1.0);  // Appendix B is the underdamped form
    const double wd = wn * std::sqrt(1 - xi * xi), sw = xi * wn, E = std::exp(-sw * T), s = std::sin(wd * T),
                 c = std::cos(wd * T), r = K2 / K3;
    const double b2 = T - E * s / wd - r * (1 - E * (sw / wd * s + c));
    const double b1 = 2 * E * (s / wd - T * c) + r * (1 - E * E) - 2 * E * s * r * sw / wd;
    const double b0 = T * E * E - E * s / wd + r * (E * E + E * (sw / wd * s - c));
    const double a1 = -2 * E * c, a0 = E * E;
    const double g = K1 * p.K_e * p.K_d * p.K_p / K3;
    const double al3 = a1 + g * b2 - 1, al2 = a0 - a1 + g * (b1 + a * b2), al1 = g * (b0 + a * b1) - a0,
                 al0 = g * a * b0;
    const DiscreteModel m = discretise(p);
    // the roots of the corrected polynomial, found here, make zI - G singular, and the largest has the modulus
    // the model reports
    auto poly = [&](std::complex<double> z) { return (((z + al3) * z + al2) * z + al1) * z + al0; };
    // roots by Durand-Kerner
    std::complex<double> roots[4] = {{0.4, 0.9}, {0.4, 0.9}, {0.4, 0.9}, {0.4, 0.9}};
    for (int i = 1; i < 4; ++i) roots[i] = roots[i - 1] * std::complex<double>(0.4, 0.9);
    for (int it = 0; it < 500; ++it)
      for (int i = 0; i < 4; ++i) {
        std::complex<double> d = 1;
        for (int j = 0; j < 4; ++j)
          if (j != i) d *= roots[i] - roots[j];
        roots[i] -= poly(roots[i]) / d;
      }
    double rho = 0;
    for (auto z : roots) rho = std::max(rho, std::abs(z));
    EXPECT_NEAR(m.spectral_radius, rho, 1e-9) << "B = " << B;
    const auto& G = m.G;
    for (auto z : roots) {
      // det(zI - G) for a 4x4 by cofactor expansion in complex arithmetic
      std::complex<double> M[4][4];
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) M[i][j] = (i == j ? z : 0.0) - G[i][j];
      auto det3 = [&](int r0, int r1, int r2, int c0, int c1, int c2) {
        return M[r0][c0] * (M[r1][c1] * M[r2][c2] - M[r1][c2] * M[r2][c1]) -
               M[r0][c1] * (M[r1][c0] * M[r2][c2] - M[r1][c2] * M[r2][c0]) +
               M[r0][c2] * (M[r1][c0] * M[r2][c1] - M[r1][c1] * M[r2][c0]);
      };
      const std::complex<double> det = M[0][0] * det3(1, 2, 3, 1, 2, 3) - M[0][1] * det3(1, 2, 3, 0, 2, 3) +
                                       M[0][2] * det3(1, 2, 3, 0, 1, 3) - M[0][3] * det3(1, 2, 3, 0, 1, 2);
      EXPECT_LT(std::abs(det), 1e-9) << "B = " << B << " z = " << z;
    }
    // Appendix C as printed (alpha_2 with - a b_2, alpha_1 with - a b_1) gives a different polynomial
    const double p2 = a0 - a1 + g * (b1 - a * b2);
    EXPECT_GT(std::abs(p2 - al2), 1e-3 * std::abs(al2));
  }
}

TEST(ServoAxis, FollowingErrorIsEq485) {
  for (double B : {0.09, 0.3, 1.0}) {
    for (double f : {5e-3, 20e-3, 50e-3}) {
      const ServoParams p = appendix_a(B);
      const double v = f / kCount;
      EXPECT_NEAR(ramp_error(p, v), eq_4_85_counts(p, v), 1e-6 * eq_4_85_counts(p, v)) << B << " " << f;
    }
  }
  // another filter: a pole too (b != 0)
  ServoParams p = appendix_a();
  p.b = -0.3;
  p.K_p = 1.5;
  EXPECT_NEAR(ramp_error(p, 10000.0, 3.0), eq_4_85_counts(p, 10000.0), 1e-6 * eq_4_85_counts(p, 10000.0));
}

TEST(ServoAxis, FollowingErrorOfThePaper) {
  // Sec. 4.3.2: f_x = f_y = 20 mm/s, B_x = 0.09, B_y = 0.3: e_sx = 0.2789 mm, e_sy = 0.3267 mm (within 1 %)
  const Drives d = read_drives_file(std::string(POLARCAM_SOURCE_DIR) + "/examples/drives/peng1989.toml");
  const double printed[2] = {0.2789e-3, 0.3267e-3};
  for (int i = 0; i < 2; ++i) {
    const double per = d.axis[i].per_count();
    EXPECT_NEAR(per, kCount, 1e-15);
    const double e = ramp_error(d.axis[i].params, 20e-3 / per) * per;
    EXPECT_NEAR(e, printed[i], 0.01 * printed[i]) << d.axis[i].name;
  }
}

TEST(ServoAxis, ErrorPerCuttingTorqueIsEq4101) {
  // a constant cutting torque on an axis at rest: the table yields by Eq. 4.101, 7.2516 counts/N m printed
  const ServoParams p = appendix_a();
  const double D1 = p.K_p * (1 + p.a) / (1 + p.b);
  const double per_Nm = (p.R_a + p.K_v * p.K_a) / (p.K_d * p.K_t * p.S_g * p.K_I * p.K_v * D1);
  ServoAxis axis(p);
  ServoSample s;
  for (int k = 0; k < 3000; ++k) s = axis.step(0.0, 1.0);
  EXPECT_NEAR(-s.X_a, per_Nm, 1e-6 * per_Nm);
  EXPECT_NEAR(-s.X_a, 7.2516, 0.001 * 7.2516);
  // the motor carries the torque: I_a = T_c/K_t, at rest
  EXPECT_NEAR(s.I_a, 1.0 / p.K_t, 1e-6);
  EXPECT_NEAR(s.W, 0.0, 1e-9);
}

TEST(ServoAxis, StepResponseSettles) {
  const ServoParams p = appendix_a();
  const DiscreteModel m = discretise(p);
  EXPECT_LT(m.spectral_radius, 1.0);
  ServoAxis axis(p);
  double peak = 0.0, last = 0.0;
  const int n = 2000;
  for (int k = 0; k < n; ++k) {
    last = axis.step(100.0).X_a;
    peak = std::max(peak, last);
    if (k * p.T > m.settling_time) {
      EXPECT_NEAR(last, 100.0, 0.01) << k;
    }
  }
  EXPECT_NEAR(last, 100.0, 1e-6);
  // Sec. 2.4.2: "well damped (without any overshoot in the step response)"; allow 1 %
  EXPECT_LT(peak, 101.0);
}

TEST(ServoAxis, Linearity) {
  const ServoParams p = appendix_a(0.3);
  std::vector<double> r1, r2, r12;
  for (int k = 0; k < 800; ++k) {
    const double t = k * p.T;
    r1.push_back(3000 * std::sin(10 * t));
    r2.push_back(k < 100 ? 0.0 : 50.0 * (t - 0.1) * (t - 0.1) * 1000);
    r12.push_back(2 * r1.back() - 3 * r2.back());
  }
  const auto a = simulate(p, r1), b = simulate(p, r2), c = simulate(p, r12);
  for (size_t k = 0; k < r1.size(); ++k) {
    EXPECT_NEAR(c[k].X_a, 2 * a[k].X_a - 3 * b[k].X_a, 1e-7 * (1 + std::abs(c[k].X_a)));
    EXPECT_NEAR(c[k].I_a, 2 * a[k].I_a - 3 * b[k].I_a, 1e-7 * (1 + std::abs(c[k].I_a)));
  }
}

TEST(ServoAxis, IntegralActionRemovesTheFollowingError) {
  // Eq. 4.107 with C_I = 0.5 (Sec. 4.4.2): a Type-2 loop, no steady error on a ramp
  ServoParams p = appendix_a(0.3);
  p.C_I = 0.5;
  EXPECT_LT(std::abs(ramp_error(p, 15748.0, 20.0)), 1e-3);
  EXPECT_GT(ramp_error(appendix_a(0.3), 15748.0, 2.0), 200.0);
}

TEST(ServoAxis, CoulombFrictionAddsItsOwnError) {
  // at constant speed Coulomb friction T_f acts like a constant cutting torque: Eq. 4.101 error on top of Eq. 4.85
  ServoParams p = appendix_a();
  p.coulomb = 0.2;
  const double D1 = p.K_p * (1 + p.a);
  const double per_Nm = (p.R_a + p.K_v * p.K_a) / (p.K_d * p.K_t * p.S_g * p.K_I * p.K_v * D1);
  const double v = 15748.0;
  EXPECT_NEAR(ramp_error(p, v), eq_4_85_counts(p, v) + 0.2 * per_Nm, 1e-6 * eq_4_85_counts(p, v));
}

TEST(ServoAxis, RefusesBadParameters) {
  ServoParams p = appendix_a();
  p.L_a = 0.0;
  EXPECT_THROW(discretise(p), InputError);
  // a filter zero or pole beyond a million: refused by name (1e308 made the loop's matrices overflow and the
  // simulation of the path run on)
  for (double big : {1e7, 1e155, -1e308}) {
    p = appendix_a();
    p.a = big;
    try {
      discretise(p);
      FAIL() << big;
    } catch (const InputError& e) {
      EXPECT_EQ(e.place(), "a");
    }
    p = appendix_a();
    p.b = big;
    EXPECT_THROW(discretise(p), InputError);
  }
  p = appendix_a();
  p.K_p = 40.0;  // unstable
  try {
    discretise(p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "K_p");
  }
}

TEST(ServoAxis, ModelReport) {
  const ServoParams p = appendix_a();
  const ModelReport r = model_report(p);
  // Eq. 4.101 evaluated with Appendix A gives 7.2574 counts/N m; printed 7.2516 (Eq. 4.102)
  EXPECT_NEAR(r.counts_per_Nm, 7.2574, 5e-5);
  EXPECT_NEAR(r.counts_per_Nm, 7.2516, 0.001 * 7.2516);
  // the filter's continuous equivalent (Eq. 3.44) keeps the DC gain of D(z)
  EXPECT_NEAR(r.K_p_prime * r.a_prime / r.b_prime, 2.5 * (1 - 0.8825), 1e-12);
  // Eq. 3.64 with K_b + K_v K_I T_g H_g falls to 1/sqrt(2) at 118.9 Hz; "about 120 Hz" (Sec. 3.4.4)
  EXPECT_NEAR(r.current_bandwidth_Hz, 118.9, 0.05);
  EXPECT_NEAR(r.current_bandwidth_Hz, 120.0, 0.02 * 120.0);
  // the sampled model's bandwidth, checked by driving the simulated axis with a sine of torque at that frequency:
  // the current's amplitude at steady state is 1/(sqrt(2) K_t) per N m
  const double f = r.current_bandwidth_discrete_Hz;
  ASSERT_GT(f, 10.0);
  ServoAxis axis(p);
  double amp = 0.0;
  const int n = 20000;
  double re = 0.0, im = 0.0;
  int m = 0;
  for (int k = 0; k < n; ++k) {
    const double t = k * p.T;
    const ServoSample s = axis.step(0.0, std::sin(2 * kPi * f * t));
    if (k >= n / 2) {  // the transient gone: the fundamental's amplitude by correlation
      re += s.I_a * std::cos(2 * kPi * f * t);
      im += s.I_a * std::sin(2 * kPi * f * t);
      ++m;
    }
  }
  amp = 2.0 * std::hypot(re, im) / m;
  EXPECT_NEAR(amp, 1.0 / (std::sqrt(2.0) * p.K_t), 0.01 / p.K_t);
}

}  // namespace tu_machine_servo_test_servo_axis
