#include "machine/servo/servo_axis.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>
#include <cmath>
#include <complex>
#include <string>

#include "cam/error.hpp"

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
  finite(p.a, "a");
  finite(p.b, "b");
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
  const Eigen::Matrix<double, 5, 5> E = M.exp();
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
  G(0, 0) = -p.b;
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
  const Eigen::VectorXcd ev = G.eigenvalues();
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
