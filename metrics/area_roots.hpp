#pragma once
// The root finders of the exact area sweep (metrics/area_error.cpp): Chebyshev values with derivatives, the
// radius and the swept area together, and the level crossings of a series, safeguarded Newton on a bracket.
#include <algorithm>
#include <cmath>

#include "digitizer/chebyshev.hpp"
#include "metrics/track_area.hpp"

namespace polarcam::area_roots {

// f, f', f'' at t (Clenshaw with its derivatives)
inline void eval3(const Cheb& c, double t, double& f, double& d1, double& d2) {
  double b1 = 0, b2 = 0, e1 = 0, e2 = 0, h1 = 0, h2 = 0;
  const double tt = 2.0 * t;
  for (int k = c.deg; k >= 1; --k) {
    const double b0 = (c.c[k] - b2) + tt * b1, e0 = (2.0 * b1 - e2) + tt * e1, h0 = (4.0 * e1 - h2) + tt * h1;
    b2 = b1, b1 = b0, e2 = e1, e1 = e0, h2 = h1, h1 = h0;
  }
  f = (c.c[0] - b2) + t * b1;
  d1 = (b1 - e2) + t * e1;
  d2 = (2.0 * e1 - h2) + t * h1;
}

// H(t) and Astar(t) in one pass. Each series is split into its even and odd parts, T_2m(t) = T_m(y) and
// T_2m+1(t) = t V_m(y) with y = 2 t^2 - 1 (V: Chebyshev polynomials of the third kind, same recurrence,
// V_0 = 1, V_1 = 2y - 1), so four independent Clenshaw recurrences of half the length run side by side: the
// evaluation is bound by the length of the longest chain, which this halves.
inline void eval_rA(const Cheb& R, const LongCheb& A, double t, double& r, double& a) {
  const double y = 2.0 * t * t - 1.0, yy = 2.0 * y;
  double re1 = 0, re2 = 0, ro1 = 0, ro2 = 0, ae1 = 0, ae2 = 0, ao1 = 0, ao2 = 0;
  const int top = std::max(A.deg, R.deg) / 2 + 1;
  for (int m = top; m >= 1; --m) {
    const int ke = 2 * m, ko = 2 * m + 1;
    const double rce = ke <= R.deg ? R.c[ke] : 0.0, rco = ko <= R.deg ? R.c[ko] : 0.0;
    const double ace = ke <= A.deg ? A.c[ke] : 0.0, aco = ko <= A.deg ? A.c[ko] : 0.0;
    const double re0 = (rce - re2) + yy * re1, ro0 = (rco - ro2) + yy * ro1;
    const double ae0 = (ace - ae2) + yy * ae1, ao0 = (aco - ao2) + yy * ao1;
    re2 = re1, re1 = re0, ro2 = ro1, ro1 = ro0, ae2 = ae1, ae1 = ae0, ao2 = ao1, ao1 = ao0;
  }
  // even: c_0 + y b_1 - b_2; odd: t (b_0 - b_1) with b_0 = c_1 + 2y b_1 - b_2
  const double r_even = (R.c[0] - re2) + y * re1, r_odd = t * (((R.deg >= 1 ? R.c[1] : 0.0) - ro2) + (yy - 1.0) * ro1);
  const double a_even = (A.c[0] - ae2) + y * ae1, a_odd = t * (((A.deg >= 1 ? A.c[1] : 0.0) - ao2) + (yy - 1.0) * ao1);
  r = r_even + r_odd;
  a = a_even + a_odd;
}

// G(t) and Astar(t) in one pass.
inline void eval_gA(const Cheb& G, const LongCheb& A, double t, double& g, double& a) { eval_rA(G, A, t, g, a); }

// Where h(t) = y on a part of a piece where h is monotone and y lies strictly between h(ta) - h_a and h(tb) - h_a
// (ya, yb). The area split there is in error by h |dh/dg| dg^2 for a crossing misplaced by dg, so the crossing
// need not be found to rounding: Newton from the interpolated guess stops once the error left after its step,
// |R''/(2 R')| dt^2, is below 1e-12 (t on [-1, 1]; far inside the rounding of the area).
inline double radius_crossing(const Cheb& R, double y, double ta, double tb, double ya, double yb) {
  double lo = std::min(ta, tb), hi = std::max(ta, tb);
  const double chord = (yb - ya) / (tb - ta);
  double t = ta + (y - ya) / chord;
  if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
  const bool up = chord > 0;  // R - y increases with t
  for (int it = 0; it < 100; ++it) {
    double v, d, d2;
    eval3(R, t, v, d, d2);
    v -= y;
    if (v == 0.0) return t;
    if ((v > 0) == up)
      hi = t;
    else
      lo = t;
    double tn = d != 0.0 ? t - v / d : 0.5 * (lo + hi);
    if (!(tn > lo && tn < hi)) {
      t = 0.5 * (lo + hi);
      continue;
    }
    const double dt = tn - t;
    if (std::abs(d2) * dt * dt <= 2e-12 * std::abs(d) || hi - lo <= 1e-15) return tn;
    t = tn;
  }
  return t;
}

// Root of f(t) = y in [lo, hi] where f - y changes sign (flo = f(lo) - y), Newton from `guess` safeguarded by
// bisection. The last Newton step is taken without another evaluation once its own error f'' dt^2 / (2 f') is
// below 1e-15 (t is on [-1, 1]).
inline double solve_level(const Cheb& f, double y, double lo, double hi, double flo, double guess) {
  if (flo == 0.0) return lo;
  double t = (guess > lo && guess < hi) ? guess : 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    double v, d1, d2;
    eval3(f, t, v, d1, d2);
    v -= y;
    if (v == 0.0) return t;
    if ((v < 0) == (flo < 0))
      lo = t;
    else
      hi = t;
    double tn = 0.5 * (lo + hi);
    if (d1 != 0.0) {
      const double dt = -v / d1;
      if (t + dt > lo && t + dt < hi) {
        tn = t + dt;
        if (std::abs(dt) <= 1e-4 && std::abs(d2 * dt * dt) <= 2e-15 * std::abs(d1)) return tn;
      }
    }
    if (hi - lo <= 4e-16) return tn;
    t = tn;
  }
  return t;
}

}  // namespace polarcam::area_roots
