#include "process/structure.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "cam/error.hpp"
#include "cam/linalg.hpp"

namespace polarcam::process {

std::complex<double> TransferFunction::operator()(std::complex<double> s) const {
  auto poly = [s](const std::vector<double>& c) {
    std::complex<double> v = 0.0;
    for (size_t i = c.size(); i-- > 0;) v = v * s + c[i];
    return v;
  };
  return poly(num) / poly(den);
}

TransferFunction workpiece_compliance(const TwoMassStructure& p) {
  // Eq. 2.2-2.3 transformed: X_m (M_m s^2 + (C_m + C_w) s + K_m + K_w) = (C_w s + K_w) X_w and
  // (M_w s^2 + C_w s + K_w) X_w - (C_w s + K_w) X_m = F_c; eliminating X_m gives Eq. 2.4 with (C_w s + K_w)^2.
  TransferFunction g;
  g.num = {p.K_m + p.K_w, p.C_m + p.C_w, p.M_m};
  g.den = {p.K_w * p.K_m,                                         // B0 = K_w (K_m + K_w) - K_w^2
           p.C_w * p.K_m + p.C_m * p.K_w,                         // B1 (Eq. 2.5g corrected, as program B.1)
           p.M_w * (p.K_m + p.K_w) + p.C_w * p.C_m + p.M_m * p.K_w,  // B2 (the C_w^2 terms cancel)
           p.M_w * (p.C_m + p.C_w) + p.M_m * p.C_w,               // B3
           p.M_m * p.M_w};                                        // B4
  return g;
}

std::complex<double> regeneration(double overlap, double period, double w) {
  const double a = w * period;
  return {1.0 - overlap * std::cos(a), overlap * std::sin(a)};
}

std::vector<std::complex<double>> poles(const TransferFunction& g) {
  std::vector<double> d = g.den;
  while (d.size() > 1 && d.back() == 0.0) d.pop_back();
  const int n = static_cast<int>(d.size()) - 1;
  std::vector<std::complex<double>> out;
  if (n < 1) return out;
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n, n);
  for (int i = 1; i < n; ++i) c(i, i - 1) = 1.0;
  for (int i = 0; i < n; ++i) c(i, n - 1) = -d[static_cast<size_t>(i)] / d[static_cast<size_t>(n)];
  const Eigen::VectorXcd roots = linalg::eigenvalues(c);
  for (int i = 0; i < n; ++i) out.push_back(roots(i));
  return out;
}

std::vector<Mode> modes(const TransferFunction& g) {
  std::vector<Mode> out;
  for (const std::complex<double> p : poles(g)) {
    if (!(p.imag() > 0.0)) continue;  // one of each conjugate pair; real poles left out
    Mode m;
    m.omega_n = std::abs(p);
    m.sigma = -p.real();
    m.zeta = m.sigma / m.omega_n;
    m.omega_d = p.imag();
    out.push_back(m);
  }
  std::sort(out.begin(), out.end(), [](const Mode& a, const Mode& b) { return a.omega_n < b.omega_n; });
  return out;
}

std::array<double, 2> undamped_frequencies(const TwoMassStructure& p) {
  // det(K - w^2 M) = 0 with M = diag(M_m, M_w), K = [[K_m + K_w, -K_w], [-K_w, K_w]]:
  // M_m M_w w^4 - (M_m K_w + M_w (K_m + K_w)) w^2 + K_m K_w = 0
  const double a = p.M_m * p.M_w, b = p.M_m * p.K_w + p.M_w * (p.K_m + p.K_w), c = p.K_m * p.K_w;
  const double disc = std::sqrt(std::max(0.0, b * b - 4.0 * a * c));
  const double hi = (b + disc) / (2.0 * a), lo = c / (a * hi);  // the product of the roots is c / a
  return {std::sqrt(lo), std::sqrt(hi)};
}

void check(const TwoMassStructure& s, const Cut& c) {
  auto positive = [](double v, const char* key, const char* what) {
    if (!(std::isfinite(v) && v > 0.0)) throw InputError(std::string("must be a positive ") + what, key);
  };
  auto nonneg = [](double v, const char* key) {
    if (!(std::isfinite(v) && v >= 0.0)) throw InputError("must be a damping of 0 or more", key);
  };
  positive(s.M_m, "structure.M_m", "mass");
  positive(s.M_w, "structure.M_w", "mass");
  positive(s.K_m, "structure.K_m", "stiffness");
  positive(s.K_w, "structure.K_w", "stiffness");
  nonneg(s.C_m, "structure.C_m");
  nonneg(s.C_w, "structure.C_w");
  if (!(std::isfinite(c.overlap) && c.overlap >= 0.0 && c.overlap <= 1.0))
    throw InputError("must be a fraction from 0 to 1", "cut.overlap");
  // a cut that overlaps the last by less than a millionth regenerates nothing measurable, and the search for its
  // limit would run on to ever higher frequencies (for every spindle speed of the lobes)
  if (c.overlap > 0.0 && c.overlap < 1e-6)
    throw InputError("must be 0 or at least 1e-6 (below that nothing regenerates: write 0)", "cut.overlap");
  positive(c.revolution_period, "cut.revolution_period", "time");
  if (!(std::isfinite(c.depth) && c.depth > 0.0)) throw InputError("must be a positive length", "cut.depth_of_cut");
  // the scale of the problem: the stability search samples the delay's period up to a few times the highest mode,
  // about 30 w T points, so w T is kept below 1e6 (a second or two); far outside that is refused, not computed
  const double w_hi = undamped_frequencies(s)[1];
  if (!(std::isfinite(w_hi) && w_hi < 1e9 && w_hi * c.revolution_period < 1e6 && w_hi * c.revolution_period > 1e-6))
    throw InputError("the structure's resonances (" + std::to_string(w_hi) +
                         " rad/s) and the revolution period are too far apart to analyse",
                     "cut.revolution_period");
  bool damped = s.C_m + s.C_w > 0.0;
  for (const std::complex<double> p : poles(workpiece_compliance(s))) damped = damped && p.real() < 0.0;
  if (!damped)
    throw InputError("every mode of the structure needs some damping: give C_m or C_w above 0", "structure.C_m");
}

}  // namespace polarcam::process
