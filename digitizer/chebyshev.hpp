#pragma once
// Chebyshev series on the reference interval t in [-1, 1]: fitting from values at the Chebyshev-Lobatto points,
// evaluation (Clenshaw), differentiation, integration and bracketed root finding. The building block of the
// polar track (polar_track.hpp): each piece of the tool path is a few such series.
#include <array>
#include <cmath>

namespace polarcam {

inline constexpr int kChebMaxDegree = 16;

struct Cheb {
  int deg = 0;  // number of coefficients - 1 after chopping
  std::array<double, kChebMaxDegree + 1> c{};

  double operator()(double t) const {
    double b1 = 0.0, b2 = 0.0;
    for (int k = deg; k >= 1; --k) {
      double b0 = c[k] + 2.0 * t * b1 - b2;
      b2 = b1;
      b1 = b0;
    }
    return c[0] + t * b1 - b2;
  }

  // value and derivative d/dt together (differentiated Clenshaw recurrence)
  void eval2(double t, double& f, double& df) const {
    double b1 = 0.0, b2 = 0.0, d1 = 0.0, d2 = 0.0;
    for (int k = deg; k >= 1; --k) {
      double b0 = c[k] + 2.0 * t * b1 - b2;
      double dd = 2.0 * b1 + 2.0 * t * d1 - d2;
      b2 = b1;
      b1 = b0;
      d2 = d1;
      d1 = dd;
    }
    f = c[0] + t * b1 - b2;
    df = b1 + t * d1 - d2;
  }

  // Series of the derivative d/dt.
  Cheb derivative() const;
  // Series of the integral from -1 to t.
  Cheb integral() const;
  // Largest |coefficient|.
  double max_abs() const;
  void scale(double k) {
    for (int i = 0; i <= deg; ++i) c[i] *= k;
  }
};

// Chebyshev-Lobatto points t_j = cos(pi j / n), j = 0..n (from +1 down to -1), n = kChebMaxDegree.
const std::array<double, kChebMaxDegree + 1>& cheb_points();
// The points halfway (in angle) between them, cos(pi (j + 1/2) / n), j = 0..n-1.
const std::array<double, kChebMaxDegree>& cheb_midpoints();

// Coefficients of the degree-n interpolant through values f_j, j = 0..n, at t_j = cos(pi j / n) (n = 8 or 16;
// the degree-8 points are every other point of cheb_points()).
Cheb cheb_fit(const double* f, int n);

// |c_{n-1}| + |c_n|: the tail that measures how well the interpolant has converged.
double cheb_tail(const Cheb& s);
// cheb_tail(cheb_fit(f, n)) without the other coefficients (the same operations: the same value).
double cheb_fit_tail(const double* f, int n);

// Drops trailing coefficients whose absolute sum stays below `tol`.
void cheb_chop(Cheb& s, double tol);

// Root of s(t) = y in [lo, hi], given that s(lo) - y and s(hi) - y do not have the same strict sign
// (fl = s(lo) - y, fh = s(hi) - y as known to the caller). Safeguarded Newton; returns t to machine precision.
double cheb_solve(const Cheb& s, double y, double lo, double hi, double fl, double fh);

// Clenshaw's recurrence on NV vectors of W lanes side by side (V: a GCC vector of W doubles): the series cc (its
// coefficients already on every lane, degree n) at the W NV points z, into out. Each lane performs
// (c_i - b_{i+2}) + 2z b_{i+1}, then (c_0 - b_2) + z b_1, in that order, with no fused multiply-add, so a value does
// not depend on its neighbours or on the width of the vectors. Inlined always, so that a caller compiled for AVX
// gets the four-lane code. The digitizer's levels (eval_levels) and the area walk's series (metrics/area_roots.hpp)
// run on it.
template <class V, int W, int NV>
__attribute__((always_inline)) inline void clenshaw_vectors(const V* cc, int n, const double* z, double* out) {
  V zz[NV], t2[NV], b1[NV], b2[NV];
  for (int v = 0; v < NV; ++v) {
    __builtin_memcpy(&zz[v], z + W * v, sizeof(V));
    t2[v] = zz[v] + zz[v];
    b1[v] = b2[v] = V{};
  }
  for (int i = n; i >= 1; --i)
    for (int v = 0; v < NV; ++v) {
      const V b0 = (cc[i] - b2[v]) + t2[v] * b1[v];
      b2[v] = b1[v];
      b1[v] = b0;
    }
  for (int v = 0; v < NV; ++v) {
    const V r = (cc[0] - b2[v]) + zz[v] * b1[v];
    __builtin_memcpy(out + W * v, &r, sizeof(V));
  }
}

}  // namespace polarcam
