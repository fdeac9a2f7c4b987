#pragma once
// Where a Chebyshev piece of an axis coordinate crosses a level, and the arc length there: the one solver of the
// polar digitizer (digitizer/digitize.cpp) and the Cartesian exact step generator (machine/cartesian/cartesian_exact.cpp).
// Inline: it is the innermost loop of both.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "digitizer/chebyshev.hpp"

namespace polarcam {

// g, g', g'', S, S', S'' at t in one Clenshaw pass (the recurrences are independent and interleave well); without
// the arc length (kWithS false) g, g', g'' alone, and s = s1 = s2 = 0.
struct GS {
  double g, g1, g2, s, s1, s2;
};
template <bool kWithS>
inline GS eval_gs(const Cheb& g, const Cheb& S, double t) {
  const int n = kWithS ? std::max(g.deg, S.deg) : g.deg;
  const double tt = 2.0 * t;
  double b1 = 0, b2 = 0, d1 = 0, d2 = 0, e1 = 0, e2 = 0, B1 = 0, B2 = 0, D1 = 0, D2 = 0, E1 = 0, E2 = 0;
  for (int k = n; k >= 1; --k) {
    double b0 = g.c[k] + tt * b1 - b2, d0 = 2.0 * b1 + tt * d1 - d2, e0 = 4.0 * d1 + tt * e1 - e2;
    b2 = b1;
    b1 = b0;
    d2 = d1;
    d1 = d0;
    e2 = e1;
    e1 = e0;
    if constexpr (kWithS) {
      double B0 = S.c[k] + tt * B1 - B2, D0 = 2.0 * B1 + tt * D1 - D2, E0 = 4.0 * D1 + tt * E1 - E2;
      B2 = B1;
      B1 = B0;
      D2 = D1;
      D1 = D0;
      E2 = E1;
      E1 = E0;
    }
  }
  if constexpr (!kWithS) return {g.c[0] + t * b1 - b2, b1 + t * d1 - d2, 2.0 * d1 + t * e1 - e2, 0.0, 0.0, 0.0};
  return {g.c[0] + t * b1 - b2, b1 + t * d1 - d2, 2.0 * d1 + t * e1 - e2,
          S.c[0] + t * B1 - B2, B1 + t * D1 - D2,   2.0 * D1 + t * E1 - E2};
}

// Two evaluations of eval_gs<true> in one pass, on two lanes of a vector: lane a evaluates the series whose
// coefficients are cg[k][a] and cs[k][a], k = n..0, at t[a]. Each lane performs exactly the operations of
// eval_gs<true> in the same order (no fused multiply-add: the build targets the baseline instruction set), so with
// the coefficients of (g_a, S) up to max(g_a.deg, S.deg) and zeros above (a leading zero coefficient leaves the
// recurrences at exact zeros) each lane's six values are bit for bit those of eval_gs<true>(g_a, S, t[a]). The
// two evaluations are independent chains of dependent multiplies and adds: run together they take little more
// time than one (the step walker solves its two axes' crossings side by side this way).
typedef double Lane2 __attribute__((vector_size(16)));
struct GS2 {
  Lane2 g, g1, g2, s, s1, s2;
};
// kSecond false: without the second derivatives (g2 = s2 = 0), a third less arithmetic; the other values are the same.
template <bool kSecond = true>
inline GS2 eval_gs2(const Lane2* cg, const Lane2* cs, int n, Lane2 t) {
  const Lane2 tt = t + t;  // 2 t, 2 b and 4 d are formed by exact additions: the same values as the products
  Lane2 b1 = {0, 0}, b2 = b1, d1 = b1, d2 = b1, e1 = b1, e2 = b1, B1 = b1, B2 = b1, D1 = b1, D2 = b1, E1 = b1, E2 = b1;
  for (int k = n; k >= 1; --k) {
    Lane2 b0 = cg[k] + tt * b1 - b2, d0 = (b1 + b1) + tt * d1 - d2;
    Lane2 B0 = cs[k] + tt * B1 - B2, D0 = (B1 + B1) + tt * D1 - D2;
    if constexpr (kSecond) {
      Lane2 e0 = ((d1 + d1) + (d1 + d1)) + tt * e1 - e2, E0 = ((D1 + D1) + (D1 + D1)) + tt * E1 - E2;
      e2 = e1;
      e1 = e0;
      E2 = E1;
      E1 = E0;
    }
    b2 = b1;
    b1 = b0;
    d2 = d1;
    d1 = d0;
    B2 = B1;
    B1 = B0;
    D2 = D1;
    D1 = D0;
  }
  return {cg[0] + t * b1 - b2, b1 + t * d1 - d2, (d1 + d1) + t * e1 - e2,
          cs[0] + t * B1 - B2, B1 + t * D1 - D2, (D1 + D1) + t * E1 - E2};
}

// eval_gs<true> with g and S on the two lanes of a vector: pk[k] = {g.c[k], S.c[k]}, k = n..0, n = max(g.deg,
// S.deg). The two lanes run the same recurrence, so each performs exactly the operations of eval_gs<true> on its
// series: the values are bit for bit the same, in half the instructions and with the accumulators in registers.
template <bool kSecond = true>
inline GS eval_gs_packed(const Lane2* pk, int n, double t) {
  const Lane2 tv = {t, t}, tt = tv + tv;  // 2 t exactly
  Lane2 b1 = {0, 0}, b2 = b1, d1 = b1, d2 = b1, e1 = b1, e2 = b1;
  for (int k = n; k >= 1; --k) {
    const Lane2 b0 = pk[k] + tt * b1 - b2, d0 = (b1 + b1) + tt * d1 - d2;
    if constexpr (kSecond) {
      const Lane2 e0 = ((d1 + d1) + (d1 + d1)) + tt * e1 - e2;
      e2 = e1;
      e1 = e0;
    }
    b2 = b1;
    b1 = b0;
    d2 = d1;
    d1 = d0;
  }
  const Lane2 v = pk[0] + tv * b1 - b2, v1 = b1 + tv * d1 - d2, v2 = (d1 + d1) + tv * e1 - e2;
  return {v[0], v1[0], v2[0], v[1], v1[1], v2[1]};
}

// A bound on |g''| over [-1, 1] for g of degree <= n with coefficients c, as eval_gs computes it: the exact bound
// sum |c_k| T_k''(1) = sum |c_k| k^2 (k^2 - 1) / 3, plus 1e-8 sum |c_k| (1 + k^4) for the rounding of the
// second-derivative recurrence (orders of magnitude above any n^4 eps growth for n <= 16).
inline double second_derivative_bound(const double* c, int n, int stride = 1) {
  double b = 0, r = 0;
  for (int k = 0; k <= n; ++k) {
    const double a = std::abs(c[k * stride]), k2 = static_cast<double>(k) * k;
    b += a * k2 * (k2 - 1.0) / 3.0;
    r += a * (1.0 + k2 * k2);
  }
  return b + 1e-8 * r;
}

struct LevelCrossing {
  double t, s;  // s = S(t), when asked for
};

// The roots found so far along a sequence of levels, for the next one's first guess: extrapolated from the last
// three (quadratic) or the last two (linear).
struct RootHistory {
  double h[3] = {0, 0, 0};
  int n = 0;
  double guess(double none) const {  // `none` while fewer than two roots are known
    if (n >= 3) return 3.0 * h[0] - 3.0 * h[1] + h[2];
    if (n >= 2) return 2.0 * h[0] - h[1];
    return none;
  }
  void push(double t) {
    h[2] = h[1];
    h[1] = h[0];
    h[0] = t;
    if (n < 3) ++n;
  }
};

// Root of g(t) = y in [lo, hi]; flo = g(lo) - y and fhi = g(hi) - y as the caller knows them (opposite signs,
// or flo == 0). Newton from `guess` with bisection as the safeguard. The last Newton step is taken without a
// further evaluation once its own error, g'' dt^2 / (2 g'), is below 1e-15 (t is on [-1, 1]) and so is that of
// the arc length extrapolated along it, S'' dt^2 / (2 S') (a coordinate linear in t, as on a theta-rho polyline,
// converges in one step while S still curves); S(t) comes with it when kWithS (the polar digitizer); a caller
// that needs S rarely leaves it out of the iteration (s is then 0).
template <bool kWithS = true>
inline LevelCrossing solve_crossing(const Cheb& g, const Cheb& S, double y, double lo, double hi, double flo, double fhi,
                                    double guess) {
  auto arc = [&](double x) { return kWithS ? S(x) : 0.0; };
  if (flo == 0.0) return {lo, arc(lo)};
  double t = guess;
  if (!(t > lo && t < hi)) {
    t = (fhi != flo) ? lo - flo * (hi - lo) / (fhi - flo) : 0.5 * (lo + hi);
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
  }
  for (int it = 0; it < 200; ++it) {
    const GS v = eval_gs<kWithS>(g, S, t);
    const double f = v.g - y;
    if (f == 0.0) return {t, v.s};
    if ((f < 0) == (flo < 0)) {
      lo = t;
      flo = f;
    } else {
      hi = t;
    }
    double tn = 0.5 * (lo + hi);
    if (v.g1 != 0.0) {
      const double dt = -f / v.g1;
      if (t + dt > lo && t + dt < hi) {
        tn = t + dt;
        if (std::abs(dt) <= 1e-4 && std::abs(v.g2 * dt * dt) <= 2e-15 * std::abs(v.g1) &&
            (!kWithS || std::abs(v.s2 * dt * dt) <= 2e-15 * std::abs(v.s1)))
          return {tn, v.s + v.s1 * dt};
      }
    }
    if (hi - lo <= 4e-16) return {tn, arc(tn)};
    t = tn;
  }
  return {t, arc(t)};
}

// solve_crossing<true> one iteration at a time, so that two solves can share evaluations (eval_gs2): start() does
// what solve_crossing does before its loop, next(v) one turn of its loop given v = eval_gs<true>(g, S, t). The
// sequence of points t and the result are those of solve_crossing<true> with the same arguments.
struct CrossingSolve {
  double t = 0, lo = 0, hi = 0, flo = 0, y = 0;
  int it = 0;
  LevelCrossing r{0, 0};

  // False when the result is already known (flo == 0): then r holds it.
  bool start(const Cheb& S, double y_, double lo_, double hi_, double flo_, double fhi, double guess) {
    y = y_;
    lo = lo_;
    hi = hi_;
    flo = flo_;
    it = 0;
    if (flo == 0.0) {
      r = {lo, S(lo)};
      return false;
    }
    t = guess;
    if (!(t > lo && t < hi)) {
      t = (fhi != flo) ? lo - flo * (hi - lo) / (fhi - flo) : 0.5 * (lo + hi);
      if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
    }
    return true;
  }
  // next() with the second derivatives asked for only when they decide: the step is accepted at once when bounds
  // bg >= |g''| and bs >= |S''| (second_derivative_bound) show the test of next() passes (bg dt^2 <= 1e-15 |g'|
  // implies |g'' dt^2| <= 2e-15 |g'| whatever the rounding); otherwise second() gives g'', S'' at t as eval_gs
  // computes them and the test of next() is made. The outcome is next()'s.
  template <class Second>
  bool next_lazy(const Cheb& S, double vg, double vg1, double vs, double vs1, double bg, double bs, Second&& second) {
    const double f = vg - y;
    if (f == 0.0) {
      r = {t, vs};
      return true;
    }
    // the bracket's side by selection: which side t falls on is as likely one as the other
    const bool low = (f < 0) == (flo < 0);
    lo = low ? t : lo;
    flo = low ? f : flo;
    hi = low ? hi : t;
    double tn = 0.5 * (lo + hi);
    if (vg1 != 0.0) {
      const double dt = -f / vg1;
      if (t + dt > lo && t + dt < hi) {
        tn = t + dt;
        if (std::abs(dt) <= 1e-4) {
          const double dt2 = dt * dt, ag1 = std::abs(vg1), as1 = std::abs(vs1);
          bool accept = ag1 >= 1e-200 && as1 >= 1e-200 && bg * dt2 <= 1e-15 * ag1 && bs * dt2 <= 1e-15 * as1;
          if (!accept) {
            const auto [vg2, vs2] = second();
            accept = std::abs(vg2 * dt * dt) <= 2e-15 * ag1 && std::abs(vs2 * dt * dt) <= 2e-15 * as1;
          }
          if (accept) {
            r = {tn, vs + vs1 * dt};
            return true;
          }
        }
      }
    }
    if (hi - lo <= 4e-16) {
      r = {tn, S(tn)};
      return true;
    }
    t = tn;
    if (++it >= 200) {
      r = {t, S(t)};
      return true;
    }
    return false;
  }
  // One iteration from the values at t; true when done (r holds the result): next_lazy with no bounds, so that the
  // second derivatives given always decide.
  bool next(const Cheb& S, double vg, double vg1, double vg2, double vs, double vs1, double vs2) {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    return next_lazy(S, vg, vg1, vs, vs1, kNone, kNone, [&] { return std::pair<double, double>{vg2, vs2}; });
  }
};

}  // namespace polarcam
