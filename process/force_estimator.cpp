// Cutting force from the feed-drive motor's current (Peng 1989, Ch. 3): see force_estimator.hpp.
#include "process/force_estimator.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "cam/error.hpp"
#include "cam/linalg.hpp"

namespace polarcam::process {
namespace {

void check(const FeedDrive& d) {
  const std::pair<const char*, double> positive[] = {
      {"B", d.B},     {"H_g", d.H_g}, {"J_e", d.J_e}, {"K_a", d.K_a}, {"K_b", d.K_b}, {"K_d", d.K_d},
      {"K_e", d.K_e}, {"K_I", d.K_I}, {"K_p", d.K_p}, {"K_v", d.K_v}, {"K_t", d.K_t}, {"L_a", d.L_a},
      {"R_a", d.R_a}, {"S_g", d.S_g}, {"T_g", d.T_g}, {"T", d.T},     {"force_per_torque", d.force_per_torque}};
  for (const auto& [name, v] : positive)
    if (!(std::isfinite(v) && v > 0.0)) throw InputError("must be a positive number", name);
  if (!(std::isfinite(d.a) && std::abs(d.a) < 1.0)) throw InputError("must be in (-1, 1)", "a");
  if (!(std::isfinite(d.b) && std::abs(d.b) < 1.0)) throw InputError("must be in (-1, 1)", "b");
}

}  // namespace

FeedDrive peng1989_drive() { return FeedDrive{}; }

std::array<double, 4> torque_estimator(const FeedDrive& d) {
  check(d);
  // Eq. 2.5-2.7: x' = A x + B u, x = [I_a, W], u = [V_c, T_c]
  Eigen::Matrix2d A, Bv;
  A << -(d.K_v * d.K_a + d.R_a) / d.L_a, -(d.K_v * d.K_I * d.T_g * d.H_g + d.K_b) / d.L_a,  //
      d.K_t / d.J_e, -d.B / d.J_e;
  Bv << d.K_v * d.K_I * d.S_g / d.L_a, 0.0,  //
      0.0, -1.0 / d.J_e;
  // Eq. 2.9-2.10 at once: exp([A B; 0 0] T) = [Phi H; 0 I]
  Eigen::Matrix4d M = Eigen::Matrix4d::Zero();
  M.topLeftCorner<2, 2>() = A * d.T;
  M.topRightCorner<2, 2>() = Bv * d.T;
  const Eigen::Matrix4d E = linalg::expm(M);
  const Eigen::Matrix2d Phi = E.topLeftCorner<2, 2>(), H = E.topRightCorner<2, 2>();
  const double det = H.determinant();
  if (!(std::isfinite(det) && std::abs(det) > 1e-300))
    throw InputError("the drive's input matrix H is singular: no estimator (Eq. 3.40)", "feed drive");
  // Eq. 3.40: u(k-1) = H^-1 x(k) - H^-1 Phi x(k-1); T_c is the second input
  const Eigen::Matrix2d Hi = H.inverse(), HiPhi = Hi * Phi;
  return {Hi(1, 0), Hi(1, 1), -HiPhi(1, 0), -HiPhi(1, 1)};
}

std::vector<double> estimate_force(const FeedDrive& d, const std::vector<double>& current_A,
                                   const std::vector<double>& speed_rad_s) {
  if (current_A.size() != speed_rad_s.size())
    throw InputError("the current and the speed must have as many samples", "estimate_force");
  if (current_A.size() < 2) throw InputError("needs at least two samples", "estimate_force");
  const auto c = torque_estimator(d);
  std::vector<double> F(current_A.size() - 1);
  for (size_t k = 1; k < current_A.size(); ++k)
    F[k - 1] = d.force_per_torque *
               (c[0] * current_A[k] + c[1] * speed_rad_s[k] + c[2] * current_A[k - 1] + c[3] * speed_rad_s[k - 1]);
  return F;
}

double steady_force_from_current(const FeedDrive& d, double current_A, double table_current_A) {
  return d.force_per_torque * d.K_t * (current_A - table_current_A);
}

CurrentSensor current_sensor(const FeedDrive& d, bool as_printed) {
  check(d);
  // the digital filter's continuous equivalent (Eq. 3.44)
  const double Kp = d.K_p * (1.0 - d.a) / (1.0 - d.b);
  const double ap = 2.0 / d.T * (1.0 + d.a) / (1.0 - d.a), bp = 2.0 / d.T * (1.0 + d.b) / (1.0 - d.b);
  const double R = d.R_a + d.K_v * d.K_a;
  const double back = d.K_b + d.K_v * d.K_I * d.T_g * d.H_g;  // volts per rad/s reaching the armature (Eq. 3.51)
  const double g = as_printed ? d.K_b * d.K_I * d.T_g * d.H_g : back;
  const double loop = d.K_d * d.K_e * Kp * d.K_v * d.K_I * d.S_g;
  CurrentSensor s;
  s.alpha[4] = d.L_a * d.J_e;
  s.alpha[3] = d.J_e * R + d.B * d.L_a + bp * d.L_a * d.J_e;
  s.alpha[2] = bp * (d.J_e * R + d.B * d.L_a) + d.B * R + d.K_t * g;
  s.alpha[1] = bp * (d.B * R + d.K_t * g) + loop * d.K_t;
  s.alpha[0] = loop * d.K_t * ap;
  s.gamma[2] = back;
  s.gamma[1] = bp * back + loop;
  s.gamma[0] = loop * ap;
  return s;
}

double current_per_torque(const CurrentSensor& s, double f_hz) {
  const std::complex<double> jw(0.0, 2.0 * std::numbers::pi * f_hz);
  std::complex<double> num = 0.0, den = 0.0;
  for (int i = 2; i >= 0; --i) num = num * jw + s.gamma[static_cast<size_t>(i)];
  for (int i = 4; i >= 0; --i) den = den * jw + s.alpha[static_cast<size_t>(i)];
  return std::abs(num / den);
}

double sensor_bandwidth_hz(const CurrentSensor& s) {
  const double target = current_per_torque(s, 0.0) / std::sqrt(2.0);
  if (!std::isfinite(target)) throw InputError("the sensor has no finite gain at 0 Hz", "feed drive");
  // scan up in steps of 1 % (from 0.01 Hz), then bisect the first step that crosses
  double lo = 0.0, hi = 0.01;
  while (current_per_torque(s, hi) > target) {
    lo = hi;
    hi *= 1.01;
    if (hi > 1e5) throw InputError("the current sensor's gain stays above 1/sqrt(2) up to 100 kHz", "feed drive");
  }
  while (hi - lo > 1e-6) {
    const double mid = 0.5 * (lo + hi);
    (current_per_torque(s, mid) > target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace polarcam::process
