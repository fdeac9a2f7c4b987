#include "machine/servo/servo_axis.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <string>

#include "cam/error.hpp"
#include "cam/linalg.hpp"

namespace polarcam::servo {
namespace {

void positive(double v, const char* key) {
  if (!(std::isfinite(v) && v > 0.0)) throw InputError("must be a positive finite number", key);
}
void finite(double v, const char* key) {
  if (!std::isfinite(v)) throw InputError("must be a finite number", key);
}

// A_c, B_c of Eq. 2.24.
void continuous(const ServoParams& p, Eigen::Matrix3d& A, Eigen::Matrix<double, 3, 2>& Bc) {
  A.setZero();
  Bc.setZero();
  A(0, 0) = -(p.K_v * p.K_a + p.R_a) / p.L_a;
  A(0, 1) = -(p.K_b + p.K_v * p.K_I * p.T_g * p.H_g) / p.L_a;
  A(1, 0) = p.K_t / p.J_e;
  A(1, 1) = -p.B / p.J_e;
  A(2, 1) = p.K_e;
  Bc(0, 0) = p.K_v * p.K_I * p.S_g / p.L_a;
  Bc(1, 1) = -1.0 / p.J_e;
}

void check_values(const ServoParams& p) {
  positive(p.R_a, "R_a");
  positive(p.L_a, "L_a");
  positive(p.K_t, "K_t");
  positive(p.J_e, "J_e");
  positive(p.K_I, "K_I");
  positive(p.K_v, "K_v");
  positive(p.S_g, "S_g");
  positive(p.K_e, "K_e");
  positive(p.K_d, "K_d");
  positive(p.K_p, "K_p");
  positive(p.T, "sample_period");
  for (auto [v, k] : {std::pair{p.K_b, "K_b"}, {p.B, "B"}, {p.K_a, "K_a"}, {p.H_g, "H_g"}, {p.T_g, "T_g"},
                      {p.C_I, "C_I"}, {p.coulomb, "coulomb"}}) {
    finite(v, k);
    if (v < 0.0) throw InputError("must not be negative", k);
  }
  // D(z)'s zero and pole are numbers of order one (Peng's a = -0.8825, b = 0): a million is far beyond any filter; the
  // loop's matrices would overflow long before a number as large as a double allows
  for (auto [v, k] : {std::pair{p.a, "a"}, {p.b, "b"}}) {
    finite(v, k);
    if (std::abs(v) > 1e6) throw InputError("must be within -1e6..1e6 (a zero or pole of the filter D(z))", k);
  }
  if (p.T > 1.0) throw InputError("must be at most 1 s", "sample_period");
}

}  // namespace

VelocityLoop velocity_loop(const ServoParams& p) {
  VelocityLoop v;
  v.K1 = p.K_t * p.S_g * p.K_I * p.K_v / (p.L_a * p.J_e);
  v.K2 = p.B / p.J_e + (p.R_a + p.K_v * p.K_a) / p.L_a;
  v.K3 = (p.B * (p.R_a + p.K_v * p.K_a) + p.K_t * (p.K_b + p.H_g * p.T_g * p.K_v * p.K_I)) / (p.J_e * p.L_a);
  return v;
}

DiscreteModel discretise(const ServoParams& p) {
  check_values(p);
  Eigen::Matrix3d A;
  Eigen::Matrix<double, 3, 2> Bc;
  continuous(p, A, Bc);
  // exp([[A, B], [0, 0]] T) = [[Phi, H], [0, I]]: the zero-order-hold equivalent (Eq. 2.9, 2.10)
  Eigen::Matrix<double, 5, 5> M = Eigen::Matrix<double, 5, 5>::Zero();
  M.block<3, 3>(0, 0) = A * p.T;
  M.block<3, 2>(0, 3) = Bc * p.T;
  const Eigen::Matrix<double, 5, 5> E = linalg::expm(M);
  DiscreteModel m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m.Phi[i][j] = E(i, j);
    for (int j = 0; j < 2; ++j) m.H[i][j] = E(i, 3 + j);
  }
  for (const auto& row : m.Phi)
    for (double v : row)
      if (!std::isfinite(v)) throw InputError("the drive's parameters give a model that overflows", "sample_period");
  // Eq. 2.31, with the error sum as a fifth state when C_I > 0
  const bool integral = p.C_I > 0.0;
  const int n = integral ? 5 : 4;
  const double kpkd = p.K_p * p.K_d;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, n), Gam = Eigen::MatrixXd::Zero(n, 2);
  G(0, 0) = 0.0 - p.b;  // +0 when b = 0
  G(0, 3) = -kpkd * (p.a - p.b);
  Gam(0, 0) = kpkd * (p.a - p.b);
  for (int i = 0; i < 3; ++i) {
    G(1 + i, 0) = m.H[i][0];
    for (int j = 0; j < 3; ++j) G(1 + i, 1 + j) = m.Phi[i][j];
    G(1 + i, 3) -= m.H[i][0] * kpkd;
    Gam(1 + i, 0) = m.H[i][0] * kpkd;
    Gam(1 + i, 1) = m.H[i][1];
    if (integral) G(1 + i, 4) = m.H[i][0] * p.K_d * p.C_I;
  }
  if (integral) {
    G(4, 3) = -p.T;
    G(4, 4) = 1.0;
    Gam(4, 0) = p.T;
  }
  m.G.assign(n, std::vector<double>(n));
  m.Gamma.assign(n, std::vector<double>(2));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) m.G[i][j] = G(i, j);
    for (int j = 0; j < 2; ++j) m.Gamma[i][j] = Gam(i, j);
  }
  const Eigen::VectorXcd ev = linalg::eigenvalues(G);
  for (int i = 0; i < n; ++i) m.spectral_radius = std::max(m.spectral_radius, std::abs(ev(i)));
  if (!(m.spectral_radius < 1.0 - 1e-12))
    throw InputError("the position loop is unstable with these parameters (an eigenvalue of G has |z| = " +
                         std::to_string(m.spectral_radius) + "): lower K_p or change a, b",
                     "K_p");
  // the slowest mode decays as |z|^k: 10 of its time constants
  m.settling_time = 10.0 * p.T / -std::log(std::max(m.spectral_radius, 1e-300));
  return m;
}

void check(const ServoParams& p) { (void)discretise(p); }

ServoAxis::ServoAxis(const ServoParams& p, double x0) : p_(p), m_(discretise(p)), X_a_(x0) {}

ServoSample ServoAxis::step(double X_r, double T_c) {
  const double e = X_r - X_a_;
  const double kpkd = p_.K_p * p_.K_d;
  ServoSample s;
  s.V_c = kpkd * e + V_d_ + p_.K_d * p_.C_I * sum_e_;
  s.I_a = I_a_;
  s.W = W_;
  s.X_a = X_a_;
  // Coulomb friction against the motion at the start of the sample, held over it (docs/feed-drives.md)
  double torque = T_c;
  if (p_.coulomb > 0.0 && W_ != 0.0) torque += W_ > 0.0 ? p_.coulomb : -p_.coulomb;
  const double x[3] = {I_a_, W_, X_a_};
  double next[3];
  for (int i = 0; i < 3; ++i)
    next[i] = m_.Phi[i][0] * x[0] + m_.Phi[i][1] * x[1] + m_.Phi[i][2] * x[2] + m_.H[i][0] * s.V_c + m_.H[i][1] * torque;
  // friction does not reverse the motion it opposes: a speed it would carry through zero stops there
  if (p_.coulomb > 0.0 && W_ != 0.0 && (next[1] > 0.0) != (W_ > 0.0) && std::abs(T_c) < p_.coulomb) next[1] = 0.0;
  V_d_ = -p_.b * V_d_ + kpkd * (p_.a - p_.b) * e;
  sum_e_ += p_.T * e;
  I_a_ = next[0];
  W_ = next[1];
  X_a_ = next[2];
  return s;
}

std::vector<ServoSample> simulate(const ServoParams& p, const std::vector<double>& X_r, double T_c) {
  ServoAxis axis(p, X_r.empty() ? 0.0 : X_r.front());
  std::vector<ServoSample> out;
  out.reserve(X_r.size());
  for (double x : X_r) out.push_back(axis.step(x, T_c));
  return out;
}

}  // namespace polarcam::servo

namespace polarcam::servo {
namespace {

// The first frequency (Hz) from f_lo up to f_hi at which mag(f) falls through `level`, by a logarithmic scan and
// bisection; 0 when it does not.
template <class F>
double first_fall(F mag, double level, double f_lo, double f_hi) {
  double a = f_lo;
  const int n = 4000;
  for (int i = 1; i <= n; ++i) {
    const double b = f_lo * std::pow(f_hi / f_lo, static_cast<double>(i) / n);
    if (mag(b) < level) {
      double lo = a, hi = b;
      for (int k = 0; k < 100; ++k) {
        const double m = 0.5 * (lo + hi);
        (mag(m) < level ? hi : lo) = m;
      }
      return 0.5 * (lo + hi);
    }
    a = b;
  }
  return 0.0;
}

}  // namespace

ModelReport model_report(const ServoParams& p) {
  ModelReport r;
  r.model = discretise(p);
  r.velocity = velocity_loop(p);
  r.omega_n = std::sqrt(r.velocity.K3);
  r.zeta = r.velocity.K2 / (2.0 * r.omega_n);
  r.K_p_prime = p.K_p * (1.0 - p.a) / (1.0 - p.b);
  r.a_prime = 2.0 / p.T * (1.0 + p.a) / (1.0 - p.a);
  r.b_prime = 2.0 / p.T * (1.0 + p.b) / (1.0 - p.b);
  const double D1 = p.K_p * (1.0 + p.a) / (1.0 + p.b);
  r.following_error_per_speed = p.C_I > 0.0 ? 0.0 : r.velocity.K3 / (r.velocity.K1 * p.K_e * p.K_d * D1);
  // a constant torque of 1 N m on the axis at rest, until the slowest mode has decayed 30 time constants
  {
    ServoAxis axis(p);
    const long n = static_cast<long>(std::ceil(3.0 * r.model.settling_time / p.T)) + 10;
    ServoSample s;
    for (long k = 0; k < n && k < 100000000L; ++k) s = axis.step(0.0, 1.0);
    s = axis.step(0.0, 1.0);
    r.counts_per_Nm = -s.X_a;
  }
  // Eq. 3.64 on the continuous model
  const double Ra = p.R_a + p.K_v * p.K_a, Kg = p.K_b + p.K_v * p.K_I * p.T_g * p.H_g, P = p.K_v * p.K_I * p.S_g;
  const double bp = r.b_prime, ap = r.a_prime, F = P * r.K_p_prime * p.K_d * p.K_e;
  const double g2 = Kg, g1 = bp * Kg + F, g0 = F * ap;
  const double a4 = p.L_a * p.J_e, a3 = p.J_e * Ra + p.B * p.L_a + bp * p.L_a * p.J_e;
  const double a2 = bp * (p.J_e * Ra + p.B * p.L_a) + p.B * Ra + p.K_t * Kg;
  const double a1 = bp * (p.B * Ra + p.K_t * Kg) + p.K_t * F, a0 = p.K_t * F * ap;
  const double rest = 1.0 / p.K_t, level = rest / std::sqrt(2.0);
  auto continuous_mag = [&](double f) {
    const std::complex<double> s(0.0, 2.0 * 3.14159265358979323846 * f);
    return std::abs((g2 * s * s + g1 * s + g0) / ((((a4 * s + a3) * s + a2) * s + a1) * s + a0));
  };
  r.current_bandwidth_Hz = first_fall(continuous_mag, level, 0.01, 1e5);
  // the sampled model: I_a(z)/T_c(z) = e_I^T (zI - G)^{-1} Gamma_T
  const int n = static_cast<int>(r.model.G.size());
  Eigen::MatrixXcd G(n, n);
  Eigen::VectorXcd g(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) G(i, j) = r.model.G[i][j];
    g(i) = r.model.Gamma[i][1];
  }
  auto discrete_mag = [&](double f) {
    const std::complex<double> z = std::exp(std::complex<double>(0.0, 2.0 * 3.14159265358979323846 * f * p.T));
    const Eigen::MatrixXcd M = z * Eigen::MatrixXcd::Identity(n, n) - G;
    return std::abs(M.partialPivLu().solve(g)(1));
  };
  r.current_bandwidth_discrete_Hz = first_fall(discrete_mag, level, 0.01, 0.5 / p.T);
  return r;
}

}  // namespace polarcam::servo
