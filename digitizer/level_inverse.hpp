#pragma once
// The arc length at a level as a polynomial of the level: the digitizer's fast path (step_walker.hpp).
//
// On an interval [ta, tb] of a track piece where an axis coordinate g(t) is strictly monotone, the arc length at
// the point where g reaches y, sigma(y) = S(g^-1(y)), is as smooth as g and S wherever g' stays away from zero.
// Its Chebyshev interpolant in z = (y - yc) ik (z in [-1, 1] over [g(ta), g(tb)]) gives the arc length of every
// level crossed on the interval by one evaluation each, with no root finding: the levels' crossings become
// independent of one another (no chain of Newton solves from extrapolated guesses).
//
// The fit needs no root finding either: the points (g(t_i), S(t_i)) at the Chebyshev-Lobatto points t_i of
// [ta, tb] lie on the graph of sigma exactly (up to the rounding of the series), so the interpolant through them is
// formed in barycentric form and re-expanded as a Chebyshev series in z. It is accepted only when
//  - g is strictly monotone at the points (as it must be on a monotone sub-interval),
//  - the last two coefficients of the degree-16 series sum to less than tol / 10 (converged), and
//  - at the 16 points of [ta, tb] halfway (in angle) between the interpolation points, which again lie on the graph
//    of sigma exactly, the series is within tol / 4 of S.
// Trailing coefficients summing to less than tol / 20 are then dropped. Where the fit is refused (an end of the
// interval near an extremum of g, where sigma has a square-root singularity, or a piece too curved for one
// polynomial) the caller splits the interval or solves the crossings one by one (level_crossing.hpp).
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "digitizer/chebyshev.hpp"
#include "digitizer/level_crossing.hpp"

namespace polarcam {

// g and S at t on the two lanes of a vector, values only: pk[k] = {g.c[k], S.c[k]}, k = n..0 (eval_gs_packed
// without derivatives).
inline Lane2 eval_value_packed(const Lane2* pk, int n, double t) {
  const Lane2 tv = {t, t}, tt = tv + tv;
  Lane2 b1 = {0, 0}, b2 = b1;
  for (int k = n; k >= 1; --k) {
    const Lane2 b0 = pk[k] + tt * b1 - b2;
    b2 = b1;
    b1 = b0;
  }
  return pk[0] + tv * b1 - b2;
}

// Cheb::operator() of s at the n points z, into out: two points on the lanes of a vector, up to eight side by side,
// so that the recurrences overlap instead of each waiting on its own chain. Each lane performs the operations of
// Cheb::operator() in the same order ((c_k + (2z) b_{k+1}) - b_{k+2}, then (c_0 + z b_1) - b_2; no fused
// multiply-add), so every value is bit for bit Cheb::operator()'s (test LevelInverse.ValuesOnLanesAreTheSeriesBitForBit).
template <int NV>
__attribute__((always_inline)) inline void cheb_values_lanes(const Cheb& s, const double* z, double* out) {
  Lane2 t[NV], t2[NV], b1[NV], b2[NV];
  for (int v = 0; v < NV; ++v) {
    __builtin_memcpy(&t[v], z + 2 * v, sizeof(Lane2));
    t2[v] = 2.0 * t[v];
    b1[v] = b2[v] = Lane2{};
  }
  for (int k = s.deg; k >= 1; --k) {
    const Lane2 c = Lane2{} + s.c[static_cast<size_t>(k)];
    for (int v = 0; v < NV; ++v) {
      const Lane2 b0 = (c + t2[v] * b1[v]) - b2[v];
      b2[v] = b1[v];
      b1[v] = b0;
    }
  }
  const Lane2 c0 = Lane2{} + s.c[0];
  for (int v = 0; v < NV; ++v) {
    const Lane2 r = (c0 + t[v] * b1[v]) - b2[v];
    __builtin_memcpy(out + 2 * v, &r, sizeof(Lane2));
  }
}
inline void cheb_values(const Cheb& s, const double* z, int n, double* out) {
  int i = 0;
  for (; i + 8 <= n; i += 8) cheb_values_lanes<4>(s, z + i, out + i);
  for (; i + 2 <= n; i += 2) cheb_values_lanes<1>(s, z + i, out + i);
  for (; i < n; ++i) out[i] = s(z[i]);
}

struct LevelInverse {
  double yc = 0, ik = 0;  // z = (y - yc) ik
  Cheb p;                 // sigma as a series in z

  double z_of(double y) const { return std::clamp((y - yc) * ik, -1.0, 1.0); }
  double operator()(double y) const { return p(z_of(y)); }
};

// sigma at the levels y_j = ((n0 + dn j) + hs) - base, j = 0..count-1 (n0, dn whole numbers: the levels of a
// grid, formed as the step walker forms them), into out[j]. The levels are independent of one another: eight at a
// time on four vectors of two lanes (clenshaw_vectors), so that four Clenshaw recurrences overlap, each ordered as
// (c_k - b_{k+2}) + 2z b_{k+1} so that a link of the chain waits on one multiply and one add. The values differ
// from LevelInverse::operator()'s by rounding alone (a few units in the last place of the arc length).
inline void eval_levels(const LevelInverse& inv, double n0, double dn, double hs, double base, size_t count,
                        double* out) {
  const int n = inv.p.deg;
  Lane2 c[kChebMaxDegree + 1];
  for (int k = 0; k <= n; ++k) c[k] = Lane2{inv.p.c[k], inv.p.c[k]};
  const Lane2 yc = {inv.yc, inv.yc}, ik = {inv.ik, inv.ik};
  const Lane2 vn0 = {n0, n0}, vdn = {dn, dn}, vhs = {hs, hs}, vb = {base, base};
  auto zs = [&](double j) {
    const Lane2 jj = {j, j + 1.0};
    const Lane2 z = (((vn0 + vdn * jj) + vhs) - vb - yc) * ik;
    return Lane2{std::clamp(z[0], -1.0, 1.0), std::clamp(z[1], -1.0, 1.0)};
  };
  size_t j = 0;
  constexpr int W = 4;  // vectors in flight
  for (; j + 2 * W <= count; j += 2 * W) {
    double z[2 * W];
    for (int w = 0; w < W; ++w) {
      const Lane2 zw = zs(static_cast<double>(j + 2 * w));
      z[2 * w] = zw[0];
      z[2 * w + 1] = zw[1];
    }
    clenshaw_vectors<Lane2, 2, W>(c, n, z, out + j);
  }
  for (; j < count; ++j) out[j] = inv(((n0 + dn * static_cast<double>(j)) + hs) - base);
}

// fit_inverse's samples at the n points t: y[i] = g(t[i]), v[K i + k] = v_k(t[i]). `sample` gives one point,
// sample(t, y, v), or, where the caller can evaluate several at once, all of them, sample(t, n, y, v).
template <int K, class Sample>
inline void fit_samples(Sample& sample, const double* t, int n, double* y, double* v) {
  if constexpr (std::is_invocable_v<Sample&, const double*, int, double*, double*>)
    sample(t, n, y, v);
  else
    for (int i = 0; i < n; ++i) sample(t[i], y[i], v + K * i);
}

// The fit of K functions v_k(t) of a track piece as series of the abscissa y = g(t) on [ta, tb], where g is
// strictly monotone: `sample` gives g and the K values (fit_samples). The points (g(t_i), v_k(t_i)) at the
// Chebyshev-Lobatto points of [ta, tb] lie on the graphs exactly (up to the rounding of the series), so each
// interpolant is formed in barycentric form in z = (y - yc) ik and re-expanded as a Chebyshev series; it is
// accepted under the tests above, function k to tol[k]. Every function shares yc and ik. With K = 1 this is
// fit_level_inverse's arithmetic, operation for operation.
template <int K, class Sample>
bool fit_inverse(Sample&& sample, double ta, double tb, const double* tol, double& yc, double& ik, Cheb* out) {
  constexpr int D = kChebMaxDegree;
  const auto& x = cheb_points();      // cos(pi j / D), from +1 down to -1
  const auto& xm = cheb_midpoints();  // cos(pi (j + 1/2) / D), halfway between
  const double tm = 0.5 * (ta + tb), hw = 0.5 * (tb - ta);
  double y[D + 1], s[K][D + 1];
  {
    double t[D + 1], v[K * (D + 1)];
    for (int i = 0; i <= D; ++i) t[i] = i == 0 ? tb : (i == D ? ta : tm + hw * x[i]);
    fit_samples<K>(sample, t, D + 1, y, v);
    for (int i = 0; i <= D; ++i)
      for (int k = 0; k < K; ++k) s[k][i] = v[K * i + k];
  }
  const double span = y[0] - y[D];
  if (!(span != 0.0) || !std::isfinite(span)) return false;
  for (int i = 0; i < D; ++i)
    if (!((y[i] - y[i + 1]) * span > 0.0)) return false;  // strictly monotone, in the direction of the ends
  yc = 0.5 * (y[0] + y[D]);
  ik = 2.0 / span;
  double z[D + 1], w[D + 1];
  for (int i = 0; i <= D; ++i) z[i] = i == 0 ? 1.0 : (i == D ? -1.0 : (y[i] - yc) * ik);
  for (int i = 0; i <= D; ++i) {
    double prod = 1.0;
    for (int j = 0; j <= D; ++j)
      if (j != i) prod *= z[i] - z[j];
    w[i] = 1.0 / prod;
  }
  // the interpolants in barycentric form at z (not a node)
  auto bary = [&](double zz, double* f) {
    double num[K] = {}, den = 0.0;
    for (int i = 0; i <= D; ++i) {
      const double q = w[i] / (zz - z[i]);
      for (int k = 0; k < K; ++k) num[k] += q * s[k][i];
      den += q;
    }
    for (int k = 0; k < K; ++k) f[k] = num[k] / den;
  };
  // the halfway points (in t) between the interpolation points: the outermost two first
  double th[D], yh[D], vh[K * D];
  for (int i = 0; i < D; ++i) th[i] = tm + hw * xm[i];
  {
    const double t2[2] = {th[0], th[D - 1]};
    double y2[2], v2[2 * K];
    fit_samples<K>(sample, t2, 2, y2, v2);
    yh[0] = y2[0], yh[D - 1] = y2[1];
    for (int k = 0; k < K; ++k) vh[k] = v2[k], vh[K * (D - 1) + k] = v2[K + k];
  }
  // refused early at the outermost halfway points, where a turn of g at an end of the interval shows first (the
  // same test as below, on the interpolant before its re-expansion)
  for (int i : {0, D - 1}) {
    const double zz = (yh[i] - yc) * ik;
    if (!(zz > z[i + 1] && zz < z[i])) return false;
    double f[K];
    bary(zz, f);
    for (int k = 0; k < K; ++k)
      if (!(std::abs(f[k] - vh[K * i + k]) <= 0.25 * tol[k])) return false;
  }
  // the interpolants at the Chebyshev-Lobatto points of z, then their Chebyshev series (DCT)
  double f[K][D + 1];
  for (int k = 0; k < K; ++k) {
    f[k][0] = s[k][0];
    f[k][D] = s[k][D];
  }
  for (int j = 1; j < D; ++j) {
    double num[K] = {}, den = 0.0;
    int hit = -1;
    for (int i = 0; i <= D; ++i) {
      const double dz = x[j] - z[i];
      if (dz == 0.0) {
        hit = i;
        break;
      }
      const double q = w[i] / dz;
      for (int k = 0; k < K; ++k) num[k] += q * s[k][i];
      den += q;
    }
    for (int k = 0; k < K; ++k) f[k][j] = hit >= 0 ? s[k][hit] : num[k] / den;
  }
  for (int k = 0; k < K; ++k) {
    out[k] = cheb_fit(f[k], D);
    if (!(std::abs(out[k].c[D]) + std::abs(out[k].c[D - 1]) <= 0.1 * tol[k])) return false;
  }
  // halfway points: on the graphs, between the interpolation points
  fit_samples<K>(sample, th + 1, D - 2, yh + 1, vh + K);
  double zh[D], fh[D];
  for (int i = 0; i < D; ++i) zh[i] = (yh[i] - yc) * ik;
  for (int k = 0; k < K; ++k) {
    cheb_values(out[k], zh, D, fh);
    for (int i = 0; i < D; ++i)
      if (!(std::abs(fh[i] - vh[K * i + k]) <= 0.25 * tol[k])) return false;
  }
  for (int k = 0; k < K; ++k) cheb_chop(out[k], 0.05 * tol[k]);
  return true;
}

// Fits sigma on [ta, tb] for the series pk (as eval_value_packed) of degree n; false when the fit is refused (see
// above). tol: the largest error in S accepted (the interpolant is checked to tol / 4).
inline bool fit_level_inverse(const Lane2* pk, int n, double ta, double tb, double tol, LevelInverse& out) {
  auto sample = [&](double t, double& y, double* v) {
    const Lane2 g = eval_value_packed(pk, n, t);
    y = g[0];
    v[0] = g[1];
  };
  return fit_inverse<1>(sample, ta, tb, &tol, out.yc, out.ik, &out.p);
}

}  // namespace polarcam
