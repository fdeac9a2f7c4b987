#include "digitizer/chebyshev.hpp"

#include <algorithm>
#include <numbers>

namespace polarcam {

namespace {
constexpr int N = kChebMaxDegree;

struct Tables {
  std::array<double, N + 1> pts;
  std::array<double, N> mids;                          // cos(pi (j + 1/2) / N)
  std::array<std::array<double, N + 1>, N + 1> cosjk;  // cos(pi j k / N)
  Tables() {
    for (int j = 0; j <= N; ++j) pts[j] = std::cos(std::numbers::pi * j / N);
    for (int j = 0; j < N; ++j) mids[j] = std::cos(std::numbers::pi * (j + 0.5) / N);
    pts[N / 2] = 0.0;
    for (int j = 0; j <= N; ++j)
      for (int k = 0; k <= N; ++k) cosjk[j][k] = std::cos(std::numbers::pi * ((j * k) % (2 * N)) / N);
  }
};
const Tables& tables() {
  static const Tables t;
  return t;
}
}  // namespace

const std::array<double, kChebMaxDegree + 1>& cheb_points() { return tables().pts; }
const std::array<double, kChebMaxDegree>& cheb_midpoints() { return tables().mids; }

Cheb cheb_fit(const double* f, int n) {
  // DCT-I: c_k = (2/n) sum'' f_j cos(pi j k / n); cos(pi j k / n) = cos(pi (j s) k / N) = cosjk[j s][k], s = N / n
  const auto& T = tables();
  const int s = N / n;
  Cheb c;
  c.deg = n;
  // every coefficient's sum side by side (the rows of the table in turn), each summed in the same order as alone:
  // the same values, with n + 1 chains in flight instead of one
  double acc[N + 1];
  for (int k = 0; k <= n; ++k) acc[k] = 0.5 * (f[0] * T.cosjk[0][k] + f[n] * T.cosjk[n * s][k]);
  for (int j = 1; j < n; ++j) {
    const double fj = f[j];
    const double* row = T.cosjk[j * s].data();
    for (int k = 0; k <= n; ++k) acc[k] += fj * row[k];
  }
  for (int k = 0; k <= n; ++k) c.c[k] = acc[k] * (2.0 / n);
  c.c[0] *= 0.5;
  c.c[n] *= 0.5;
  return c;
}

double cheb_fit_tail(const double* f, int n) {
  const auto& T = tables();
  const int s = N / n;
  double c[2];
  for (int q = 0; q < 2; ++q) {
    const int k = n - 1 + q;
    double acc = 0.5 * (f[0] * T.cosjk[0][k] + f[n] * T.cosjk[n * s][k]);
    for (int j = 1; j < n; ++j) acc += f[j] * T.cosjk[j * s][k];
    c[q] = acc * (2.0 / n);
    if (k == 0 || k == n) c[q] *= 0.5;
  }
  return std::abs(c[1]) + std::abs(c[0]);
}

double cheb_tail(const Cheb& s) {
  if (s.deg < 1) return 0.0;
  return std::abs(s.c[s.deg]) + std::abs(s.c[s.deg - 1]);
}

void cheb_chop(Cheb& s, double tol) {
  double acc = 0.0;
  while (s.deg > 0 && acc + std::abs(s.c[s.deg]) < tol) {
    acc += std::abs(s.c[s.deg]);
    s.c[s.deg] = 0.0;
    --s.deg;
  }
}

double Cheb::max_abs() const {
  double m = 0.0;
  for (int i = 0; i <= deg; ++i) m = std::max(m, std::abs(c[i]));
  return m;
}

Cheb Cheb::derivative() const {
  Cheb d;
  if (deg == 0) return d;
  d.deg = deg - 1;
  std::array<double, N + 2> cd{};
  for (int k = deg; k >= 1; --k) cd[k - 1] = cd[k + 1] + 2.0 * k * c[k];
  cd[0] *= 0.5;
  for (int k = 0; k <= d.deg; ++k) d.c[k] = cd[k];
  return d;
}

Cheb Cheb::integral() const {
  // integral of T_k: T_{k+1}/(2(k+1)) - T_{k-1}/(2(k-1)); the result must fit the fixed degree, so the input
  // degree is at most N - 1 in practice (callers chop first); a degree-N input drops its top term's T_{N+1} part
  // only if it is negligible, which cheb_chop has already ensured.
  Cheb I;
  int n = std::min(deg + 1, N);
  I.deg = n;
  std::array<double, N + 3> a{};
  for (int k = 0; k <= deg; ++k) a[k] = c[k];
  for (int k = 1; k <= n; ++k) I.c[k] = (a[k - 1] - a[k + 1]) / (2.0 * k);
  I.c[1] += 0.5 * a[0];  // T_0 integrates to T_1 (coefficient a0, not the a0/2 of the general formula)
  // value at t = -1 must be zero: T_k(-1) = (-1)^k
  double v = 0.0;
  for (int k = 1; k <= n; ++k) v += (k % 2 ? -1.0 : 1.0) * I.c[k];
  I.c[0] = -v;
  return I;
}

double cheb_solve(const Cheb& s, double y, double lo, double hi, double fl, double fh) {
  if (fl == 0.0) return lo;
  if (fh == 0.0) return hi;
  if ((fl > 0) == (fh > 0)) return std::abs(fl) <= std::abs(fh) ? lo : hi;  // not bracketed by rounding
  // secant start
  double t = lo - fl * (hi - lo) / (fh - fl);
  if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
  for (int it = 0; it < 60; ++it) {
    double f, df;
    s.eval2(t, f, df);
    f -= y;
    if (f == 0.0) return t;
    if ((f > 0) == (fh > 0)) {
      hi = t;
      fh = f;
    } else {
      lo = t;
      fl = f;
    }
    double tn = t - f / df;
    if (!(tn > lo && tn < hi)) tn = 0.5 * (lo + hi);
    if (std::abs(tn - t) <= 2.5e-16 * std::max(1.0, std::abs(t)) || hi - lo <= 2.5e-16 * std::max(1.0, std::abs(t))) return tn;
    t = tn;
  }
  return t;
}

}  // namespace polarcam
