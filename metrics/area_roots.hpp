#pragma once
// The root finders of the exact area sweep (metrics/area_error.cpp): Chebyshev values with derivatives, the
// radius and the swept area together, and the level crossings of a series, safeguarded Newton on a bracket.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "digitizer/chebyshev.hpp"
#include "digitizer/level_crossing.hpp"
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

// The series of two pieces side by side, for the two lanes of a vector: H (the radius less its base), and G (the
// abscissa) and Astar split into their even and odd parts as eval_rA splits them, each lane's coefficients up to
// the larger degree and zeros above. Prepared once for a pair of pieces (consecutive sectors mostly share theirs),
// it spares the evaluations below a test and a selection per coefficient.
struct PairSeries {
  int n = 0;  // H: the larger degree
  Lane2 h[kChebMaxDegree + 1];
  int top = 0;  // G and Astar: eval_rA's top of the two
  Lane2 ge[kLongChebMaxDegree / 2 + 3], go[kLongChebMaxDegree / 2 + 3], ae[kLongChebMaxDegree / 2 + 3],
      ao[kLongChebMaxDegree / 2 + 3];
};
inline void prepare_pair(PairSeries& s, const Cheb& H0, const Cheb& H1, const Cheb& G0, const LongCheb& A0,
                         const Cheb& G1, const LongCheb& A1) {
  auto c = [](const Cheb& f, int k) { return k <= f.deg ? f.c[static_cast<size_t>(k)] : 0.0; };
  auto l = [](const LongCheb& f, int k) { return k <= f.deg ? f.c[static_cast<size_t>(k)] : 0.0; };
  s.n = std::max(H0.deg, H1.deg);
  for (int k = 0; k <= s.n; ++k) s.h[k] = Lane2{c(H0, k), c(H1, k)};
  s.top = std::max({A0.deg, G0.deg, A1.deg, G1.deg}) / 2 + 1;
  for (int m = 0; m <= s.top; ++m) {
    const int ke = 2 * m, ko = 2 * m + 1;
    s.ge[m] = Lane2{c(G0, ke), c(G1, ke)}, s.go[m] = Lane2{c(G0, ko), c(G1, ko)};
    s.ae[m] = Lane2{l(A0, ke), l(A1, ke)}, s.ao[m] = Lane2{l(A0, ko), l(A1, ko)};
  }
}

// f, f', f'' of the pair's H at two points: lane a performs exactly the operations of eval3(H_a, t[a]) in the same
// order (no fused multiply-add: the build targets the baseline instruction set; the products by 2 and 4 are exact
// additions), from the larger degree (a leading zero coefficient leaves the recurrences at exact zeros), so each
// lane's values are bit for bit those of eval3. Two independent chains of dependent multiplies and adds take little
// more time than one.
// S: PairSeries or QuadSeries, V: its lanes. Inlined always, so that the four-lane copy is compiled inside eval3_4
// (with AVX).
// The recurrence itself, on NV vectors side by side (h: the coefficients already on every lane): the value and the
// two derivatives at t[v] into f[v], d1[v], d2[v]. The radius's crossings on the fits (fit_search_lanes) run it on
// pairs of vectors, eval3_lanes on one.
template <class V, int NV>
__attribute__((always_inline)) inline void eval3_vectors(const V* h, int n, const V* t, V* f, V* d1, V* d2) {
  V b1[NV], b2[NV], e1[NV], e2[NV], h1[NV], h2[NV], tt[NV];
  for (int v = 0; v < NV; ++v) {
    tt[v] = t[v] + t[v];
    b1[v] = b2[v] = e1[v] = e2[v] = h1[v] = h2[v] = V{};
  }
  for (int k = n; k >= 1; --k)
    for (int v = 0; v < NV; ++v) {
      const V b0 = (h[k] - b2[v]) + tt[v] * b1[v], e0 = ((b1[v] + b1[v]) - e2[v]) + tt[v] * e1[v];
      const V h0 = (((e1[v] + e1[v]) + (e1[v] + e1[v])) - h2[v]) + tt[v] * h1[v];
      b2[v] = b1[v], b1[v] = b0, e2[v] = e1[v], e1[v] = e0, h2[v] = h1[v], h1[v] = h0;
    }
  for (int v = 0; v < NV; ++v) {
    f[v] = (h[0] - b2[v]) + t[v] * b1[v];
    d1[v] = (b1[v] - e2[v]) + t[v] * e1[v];
    d2[v] = ((e1[v] + e1[v]) - h2[v]) + t[v] * h1[v];
  }
}
template <class S, class V>
__attribute__((always_inline)) inline void eval3_lanes(const S& s, const V& t, V& f, V& d1, V& d2) {
  eval3_vectors<V, 1>(s.h, s.n, &t, &f, &d1, &d2);
}
inline void eval3_2(const PairSeries& s, Lane2 t, Lane2& f, Lane2& d1, Lane2& d2) { eval3_lanes(s, t, f, d1, d2); }

// eval_rA of the pair's G and Astar at two points: each lane bit for bit eval_rA's values (the same operations in
// the same order; the loop runs from the larger top, whose leading zero coefficients leave the recurrences at
// exact zeros, as eval_rA's own top does).
// S: PairSeries or QuadSeries, V: its lanes; inlined always, as eval3_lanes.
template <class S, class V>
__attribute__((always_inline)) inline void eval_rA_lanes(const S& s, const V& t, V& r, V& a) {
  const V two = V{} + 2.0, one = V{} + 1.0;
  const V y = two * t * t - one, yy = two * y;
  V re1 = V{}, re2 = re1, ro1 = re1, ro2 = re1, ae1 = re1, ae2 = re1, ao1 = re1, ao2 = re1;
  for (int m = s.top; m >= 1; --m) {
    const V re0 = (s.ge[m] - re2) + yy * re1, ro0 = (s.go[m] - ro2) + yy * ro1;
    const V ae0 = (s.ae[m] - ae2) + yy * ae1, ao0 = (s.ao[m] - ao2) + yy * ao1;
    re2 = re1, re1 = re0, ro2 = ro1, ro1 = ro0, ae2 = ae1, ae1 = ae0, ao2 = ao1, ao1 = ao0;
  }
  // even: c_0 + y b_1 - b_2; odd: t (b_0 - b_1) with b_0 = c_1 + 2y b_1 - b_2
  const V r_even = (s.ge[0] - re2) + y * re1, r_odd = t * ((s.go[0] - ro2) + (yy - one) * ro1);
  const V a_even = (s.ae[0] - ae2) + y * ae1, a_odd = t * ((s.ao[0] - ao2) + (yy - one) * ao1);
  r = r_even + r_odd;
  a = a_even + a_odd;
}
inline void eval_rA2(const PairSeries& s, Lane2 t, Lane2& r, Lane2& a) { eval_rA_lanes(s, t, r, a); }

// Where h(t) = y on a part of a piece where h is monotone and y lies strictly between h(ta) - h_a and h(tb) - h_a
// (ya, yb). The area split there is in error by h |dh/dg| dg^2 for a crossing misplaced by dg, so the crossing
// need not be found to rounding: Newton from the interpolated guess stops once the error left after its step,
// |R''/(2 R')| dt^2, is below 1e-12 (t on [-1, 1]; far inside the rounding of the area). The search's state, one
// step at a time: radius_crossing runs it on one series, radius_crossing2 on two side by side.
// Its fields are set by start() alone (no initializers: an array of four of them would be zeroed at every batch
// of crossings, a string store that cost as much as a fifth of the batch's own work).
struct RadiusCrossing {
  double lo, hi, t, y;
  bool up;
  int it;
  void start(double y_, double ta, double tb, double ya, double yb) {
    y = y_;
    it = 0;
    lo = std::min(ta, tb), hi = std::max(ta, tb);
    const double chord = (yb - ya) / (tb - ta);
    t = ta + (y - ya) / chord;
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
    up = chord > 0;  // R - y increases with t
  }
  // One step from t, given R, R', R'' there: true when t is the crossing (or the search has run 100 steps).
  bool next(double v, double d, double d2) {
    v -= y;
    if (v == 0.0) return true;
    if ((v > 0) == up)
      hi = t;
    else
      lo = t;
    const double tn = d != 0.0 ? t - v / d : 0.5 * (lo + hi);
    if (!(tn > lo && tn < hi)) {
      t = 0.5 * (lo + hi);
      return ++it >= 100;
    }
    const double dt = tn - t;
    t = tn;
    if (std::abs(d2) * dt * dt <= 2e-12 * std::abs(d) || hi - lo <= 1e-15) return true;
    return ++it >= 100;
  }
};

// The search from its state to its end, on one series (c.t is then the crossing).
inline void run_crossing(const Cheb& R, RadiusCrossing& c) {
  for (;;) {
    double v, d, d2;
    eval3(R, c.t, v, d, d2);
    if (c.next(v, d, d2)) return;
  }
}

inline double radius_crossing(const Cheb& R, double y, double ta, double tb, double ya, double yb) {
  RadiusCrossing c;
  c.start(y, ta, tb, ya, yb);
  run_crossing(R, c);
  return c.t;
}

// Two crossings side by side (each as radius_crossing's, bit for bit), of the pair's H (R0 and R1); the one left
// when the other is done goes on alone.
inline void radius_crossing2(const PairSeries& s, const Cheb& R0, const Cheb& R1, RadiusCrossing& c0,
                             RadiusCrossing& c1) {
  bool done0 = false, done1 = false;
  while (!done0 && !done1) {
    Lane2 v, d, d2;
    eval3_2(s, Lane2{c0.t, c1.t}, v, d, d2);
    done0 = c0.next(v[0], d[0], d2[0]);
    done1 = c1.next(v[1], d[1], d2[1]);
  }
  if (!done0) run_crossing(R0, c0);
  if (!done1) run_crossing(R1, c1);
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

// Four crossings side by side on the four lanes of a 256-bit vector (AVX), each lane bit for bit the one-at-a-time
// search and evaluation, as two lanes are above: the same operations in the same order, no fused multiply-add (AVX
// has none; the target attribute enables AVX alone). Only for processors that have AVX: has_avx() says so at run
// time, and the meter finds its crossings two at a time otherwise (the same values).
typedef double Lane4 __attribute__((vector_size(32)));
struct QuadSeries {
  int n = 0;
  Lane4 h[kChebMaxDegree + 1];
  int top = 0;
  Lane4 ge[kLongChebMaxDegree / 2 + 3], go[kLongChebMaxDegree / 2 + 3], ae[kLongChebMaxDegree / 2 + 3],
      ao[kLongChebMaxDegree / 2 + 3];
};
inline void prepare_quad(QuadSeries& s, const Cheb* const H[4], const Cheb* const G[4], const LongCheb* const A[4]) {
  auto c = [](const Cheb& f, int k) { return k <= f.deg ? f.c[static_cast<size_t>(k)] : 0.0; };
  auto l = [](const LongCheb& f, int k) { return k <= f.deg ? f.c[static_cast<size_t>(k)] : 0.0; };
  s.n = 0;
  s.top = 0;
  for (int q = 0; q < 4; ++q) {
    s.n = std::max(s.n, H[q]->deg);
    s.top = std::max({s.top, A[q]->deg / 2 + 1, G[q]->deg / 2 + 1});
  }
  for (int k = 0; k <= s.n; ++k) s.h[k] = Lane4{c(*H[0], k), c(*H[1], k), c(*H[2], k), c(*H[3], k)};
  for (int m = 0; m <= s.top; ++m) {
    const int ke = 2 * m, ko = 2 * m + 1;
    s.ge[m] = Lane4{c(*G[0], ke), c(*G[1], ke), c(*G[2], ke), c(*G[3], ke)};
    s.go[m] = Lane4{c(*G[0], ko), c(*G[1], ko), c(*G[2], ko), c(*G[3], ko)};
    s.ae[m] = Lane4{l(*A[0], ke), l(*A[1], ke), l(*A[2], ke), l(*A[3], ke)};
    s.ao[m] = Lane4{l(*A[0], ko), l(*A[1], ko), l(*A[2], ko), l(*A[3], ko)};
  }
}

inline bool has_avx() {
  static const bool yes = __builtin_cpu_supports("avx");
  return yes;
}

// eval3_2 on four lanes.
__attribute__((target("avx"))) inline void eval3_4(const QuadSeries& s, Lane4 t, Lane4& f, Lane4& d1, Lane4& d2) {
  eval3_lanes(s, t, f, d1, d2);
}

// eval_rA2 on four lanes.
__attribute__((target("avx"))) inline void eval_rA4(const QuadSeries& s, Lane4 t, Lane4& r, Lane4& a) {
  eval_rA_lanes(s, t, r, a);
}

// The samples of a fit of the walk (StairAreaMeter::walk_fit) four at a time: g = G(t) as Cheb::operator()
// computes it, ((c_k + 2t b_{k+1}) - b_{k+2}), then ((c_0 + t b_1) - b_2), and r, a as eval_rA(R, A, t) computes
// them, each lane those operations in the same order (no fused multiply-add), so the values are eval_rA's and
// G's bit for bit. s is prepared by prepare_fit. The last group of four repeats the last point.
// eval_g_rA4's series: one piece's G, R and Astar on every lane (prepare_quad with G in the place of H and R in the
// place of G: s.h holds G's coefficients, s.ge and s.go R's).
inline void prepare_fit(QuadSeries& s, const Cheb& G, const Cheb& R, const LongCheb& A) {
  const Cheb* const g4[4] = {&G, &G, &G, &G};
  const Cheb* const r4[4] = {&R, &R, &R, &R};
  const LongCheb* const a4[4] = {&A, &A, &A, &A};
  prepare_quad(s, g4, r4, a4);
}

__attribute__((target("avx"))) inline void eval_g_rA4(const QuadSeries& s, const double* t, int n, double* g, double* r,
                                                      double* a) {
  for (int i = 0; i < n; i += 4) {
    Lane4 tv;
    for (int q = 0; q < 4; ++q) tv[q] = t[std::min(i + q, n - 1)];
    const Lane4 tt = (Lane4{} + 2.0) * tv;
    Lane4 b1 = Lane4{}, b2 = b1;
    for (int k = s.n; k >= 1; --k) {
      const Lane4 b0 = (s.h[k] + tt * b1) - b2;
      b2 = b1;
      b1 = b0;
    }
    const Lane4 gv = (s.h[0] + tv * b1) - b2;
    Lane4 rv, av;
    eval_rA_lanes(s, tv, rv, av);
    for (int q = 0; q < 4 && i + q < n; ++q) g[i + q] = gv[q], r[i + q] = rv[q], a[i + q] = av[q];
  }
}

// Four crossings side by side (each radius_crossing's, bit for bit): the lanes still searching step together, a
// lane that is done keeps its crossing; then the abscissa g and Astar a at each crossing (eval_rA's values).
__attribute__((target("avx"))) inline void radius_crossing4(const QuadSeries& s, RadiusCrossing c[4], double g[4],
                                                             double a[4]) {
  bool done[4] = {false, false, false, false};
  while (!(done[0] && done[1] && done[2] && done[3])) {
    Lane4 v, d, d2;
    eval3_4(s, Lane4{c[0].t, c[1].t, c[2].t, c[3].t}, v, d, d2);
    for (int q = 0; q < 4; ++q)
      if (!done[q]) done[q] = c[q].next(v[q], d[q], d2[q]);
  }
  Lane4 gv, av;
  eval_rA4(s, Lane4{c[0].t, c[1].t, c[2].t, c[3].t}, gv, av);
  for (int q = 0; q < 4; ++q) g[q] = gv[q], a[q] = av[q];
}

// The series c (degree n) at the points z[0..cnt), into out. Each lane of a vector performs the operations of one
// Clenshaw recurrence, (c_i - b_{i+2}) + 2z b_{i+1}, then (c_0 - b_2) + z b_1, in that order (no fused multiply-add),
// so a value is the same whichever points share its vector and however wide the vectors are: sixteen points at a
// time on four vectors of four lanes where the processor has AVX, eight on four vectors of two lanes otherwise;
// four recurrences are in flight either way. cnt is rounded up to a multiple of eight (sixteen): z and out must
// have room for as many.
// V: a vector of W lanes. Inlined always, so that the four-lane copy is compiled inside clenshaw_many4 (with AVX).
template <class V, int W>
__attribute__((always_inline)) inline void clenshaw_lanes(const double* c, int n, const double* z, size_t cnt,
                                                          double* out) {
  V cc[kChebMaxDegree + 1];
  for (int i = 0; i <= n; ++i)
    for (int q = 0; q < W; ++q) cc[i][q] = c[i];
  for (size_t j = 0; j < cnt; j += 4 * W) clenshaw_vectors<V, W, 4>(cc, n, z + j, out + j);
}

// clenshaw_lanes's operations for one point z: the same value as the lane that holds z.
inline double clenshaw_one(const double* c, int n, double z) {
  const double t2 = z + z;
  double b1 = 0.0, b2 = 0.0;
  for (int i = n; i >= 1; --i) {
    const double b0 = (c[i] - b2) + t2 * b1;
    b2 = b1;
    b1 = b0;
  }
  return (c[0] - b2) + z * b1;
}

inline void clenshaw_many2(const double* c, int n, const double* z, size_t cnt, double* out) {
  clenshaw_lanes<Lane2, 2>(c, n, z, cnt, out);
}

__attribute__((target("avx"))) inline void clenshaw_many4(const double* c, int n, const double* z, size_t cnt,
                                                          double* out) {
  clenshaw_lanes<Lane4, 4>(c, n, z, cnt, out);
}

// The crossings of a stretch of the walk (StairAreaMeter::walk_fit) found on the stretch's fits: where the fit of
// the radius H (a series in the fit's variable z) reaches each column's level, then the fit of Astar, A, there.
// Every lane performs its own operations in the same order whatever the other lanes hold, so a value is the same
// however the columns are grouped, and with vectors of two lanes or four. The fits are within a few units of
// rounding of the piece's series (StairAreaMeter::walk_piece_start), and an error dz in a crossing moves the area by
// a term in dz^2 only.
// The two fits' coefficients on every lane of a vector V, prepared once for a stretch.
template <class V>
struct FitCrossingSeries {
  int n = 0, na = 0;
  V h[kChebMaxDegree + 1], a[kChebMaxDegree + 1];
  V m4;   // SeriesBounds::m4
  V eps;  // SeriesBounds::rounding, doubled
};
// Bounds on a series H on [-1, 1], from its coefficients, for the certificates of the dense walk's crossings and
// half levels. The derivatives of T_k are largest at the ends, where Markov's inequality is an equality:
// |T_k'| <= k^2 and |T_k''''| <= k^2 (k^2 - 1) (k^2 - 4) (k^2 - 9) / 105.
struct SeriesBounds {
  double m1 = 0.0;        // |H'|: sum of k^2 |c_k|
  double m4 = 0.0;        // |H''''|: sum over k >= 4 of |c_k| T_k''''(1)
  double rounding = 0.0;  // of Clenshaw's recurrence at a point: (n + 1)^2 units of rounding of sum |c_k| (its
                          // error grows at most as the square of the degree)
};
inline SeriesBounds series_bounds(const Cheb& H) {
  SeriesBounds b;
  double sum = 0.0;
  for (int k = 0; k <= H.deg; ++k) {
    const double c = std::abs(H.c[static_cast<size_t>(k)]), kk = static_cast<double>(k) * k;
    sum += c;
    b.m1 += c * kk;
    if (k >= 4) b.m4 += c * (kk * (kk - 1.0) * (kk - 4.0) * (kk - 9.0) / 105.0);
  }
  const double n1 = static_cast<double>(H.deg) + 1.0;
  b.rounding = n1 * n1 * 0x1p-52 * sum;
  return b;
}
template <class V>
inline void prepare_fit_crossings(FitCrossingSeries<V>& s, const Cheb& H, const Cheb& A, const SeriesBounds& b) {
  s.n = H.deg;
  s.na = A.deg;
  s.m4 = V{} + b.m4;
  s.eps = V{} + 2.0 * b.rounding;
  for (int k = 0; k <= H.deg; ++k)
    for (size_t q = 0; q < sizeof(V) / sizeof(double); ++q) s.h[k][q] = H.c[static_cast<size_t>(k)];
  for (int k = 0; k <= A.deg; ++k)
    for (size_t q = 0; q < sizeof(V) / sizeof(double); ++q) s.a[k][q] = A.c[static_cast<size_t>(k)];
}
// The columns' crossings, up to sixteen at a time (FitCrossings::n of them, at least one; fit_crossings fills the
// spare lanes of its last vector with the last column): column q
// runs from z0[q] to z1[q] in the fit's variable, where the fit of the radius is h0[q] and h1[q], and y[q] is its
// level (between the two). The search is RadiusCrossing's, on every lane at once with no branch on a lane's own
// state (a bracketing interval, Newton's step where it stays inside, halving otherwise; done once the error left
// after a step, |H''/(2 H')| dz^2, is below 1e-12, or the interval is below 1e-15): the processor cannot guess which
// way a lane goes. Out: z[q], the crossing, and a[q], the fit of Astar there.
// Before the search, each column's crossing is taken from the cubic through the fit's values v at four edges, u = 0,
// 1, 2, 3 a column apart: the column runs from u = ua[q] to ua[q] + 1 (1: the column and one edge on each side; 0 and
// 2: a stretch's first and last column, the four edges at its end), with one Newton step on that cubic from the
// chord. It is kept where it is certified. With M4 the bound on |H''''| and w = |z1 - z0|, the cubic is within
// M4 w^4 |node polynomial| / 4! of H on the column (the node polynomial at most 9/16 w^4 on the middle column, w^4
// on an end one), plus the rounding of the four values (eps) and of the edges' places (a few units in the last
// place of z, times |H'|); its derivative is within 27 M4 w^3 of H's (Rolle's theorem three times over the nodes'
// span of 3 w). Where the derivative keeps its sign with a margin m1 > 0 on the column, the crossing is within
// dz = (those errors + |p(u) - y|) / m1 of H's. A crossing misplaced by dz moves the column's part by at most
// |f'| dz^2, f the part's integrand; with f' = hf[q] width H' / w in the fit's variable (hf: the largest radius of
// the column in the polar geometry, 1 in the Cartesian one; width: the abscissa per column), the crossing is kept
// where that is at most bud[q] (the walk's budget: a thousandth of a unit in the last place of the values the part
// is formed from; 0 keeps none). The columns where it is not, and those whose radius turns, are searched as before
// (searched_q marks them).
struct FitCrossings {
  static constexpr int kMax = 16;
  alignas(32) double z0[kMax], z1[kMax], h0[kMax], h1[kMax], y[kMax], z[kMax], a[kMax];
  alignas(32) double v[4][kMax], ua[kMax], hf[kMax], bud[kMax];
  double width = 0.0;
  int n = 0;
  uint32_t searched_q = 0;  // the columns of the last batch whose crossings were searched: bit q for column q
};
template <class V>
inline void prepare_fit_crossings(FitCrossingSeries<V>& s, const Cheb& H, const Cheb& A) {
  prepare_fit_crossings(s, H, A, series_bounds(H));
}
// The lanes' masks: a comparison of two vectors of doubles gives one of 64-bit integers, all ones where true.
typedef long long Mask2 __attribute__((vector_size(16)));
typedef long long Mask4 __attribute__((vector_size(32)));
template <class V>
struct MaskOf;
template <>
struct MaskOf<Lane2> {
  typedef Mask2 type;
};
template <>
struct MaskOf<Lane4> {
  typedef Mask4 type;
};
// (the lanes of a where m is set, of b elsewhere; |a|): written out where used, since a helper taking or returning
// a 256-bit vector by value outside an AVX function is refused by clang)
#define POLARCAM_PICK(m, a, b) ((V)((((M)(a)) & (m)) | (((M)(b)) & ~(m))))
#define POLARCAM_ABS(a) ((V)(((M)(a)) & ~sign))

// The search on NV vectors of W lanes side by side, from lane W * v0 on: the crossings into x.z. Inlined always, so
// that the four-lane copy is compiled inside fit_crossings (with AVX).
template <class V, int W, int NV>
__attribute__((always_inline)) inline void fit_search_lanes(const FitCrossingSeries<V>& s, FitCrossings& x, int v0) {
  typedef typename MaskOf<V>::type M;
  const M sign = (M)(-V{});  // -0.0: the sign bit alone
  const V half = V{} + 0.5;
  V t[NV], lo[NV], hi[NV], y[NV];
  M up[NV], done[NV];
  for (int v = 0; v < NV; ++v) {
    V ta, tb, ya, yb;
    __builtin_memcpy(&ta, x.z0 + W * (v0 + v), sizeof(V));
    __builtin_memcpy(&tb, x.z1 + W * (v0 + v), sizeof(V));
    __builtin_memcpy(&ya, x.h0 + W * (v0 + v), sizeof(V));
    __builtin_memcpy(&yb, x.h1 + W * (v0 + v), sizeof(V));
    __builtin_memcpy(&y[v], x.y + W * (v0 + v), sizeof(V));
    const M less = ta < tb;
    lo[v] = POLARCAM_PICK(less, ta, tb);
    hi[v] = POLARCAM_PICK(less, tb, ta);
    const V chord = (yb - ya) / (tb - ta), t0 = ta + (y[v] - ya) / chord;
    t[v] = POLARCAM_PICK((t0 > lo[v]) & (t0 < hi[v]), t0, half * (lo[v] + hi[v]));
    up[v] = chord > V{};
    done[v] = M{};
  }
  for (int it = 0; it < 100; ++it) {
    V fv[NV], d1v[NV], d2v[NV];
    eval3_vectors<V, NV>(s.h, s.n, t, fv, d1v, d2v);
    M all = ~M{};
    for (int v = 0; v < NV; ++v) {
      const V f = fv[v] - y[v], d1 = d1v[v], d2 = d2v[v];
      const M zero = f == V{}, above = ~((f > V{}) ^ up[v]);
      const V nlo = POLARCAM_PICK(above, lo[v], t[v]), nhi = POLARCAM_PICK(above, t[v], hi[v]);
      const V tn = t[v] - f / d1, dt = tn - t[v];
      const M inside = (tn > nlo) & (tn < nhi);
      const M conv =
          inside & ((POLARCAM_ABS(d2) * dt * dt <= (V{} + 2e-12) * POLARCAM_ABS(d1)) | (nhi - nlo <= V{} + 1e-15));
      const M move = ~done[v] & ~zero;
      t[v] = POLARCAM_PICK(move, POLARCAM_PICK(inside, tn, half * (nlo + nhi)), t[v]);
      lo[v] = POLARCAM_PICK(move, nlo, lo[v]);
      hi[v] = POLARCAM_PICK(move, nhi, hi[v]);
      done[v] = done[v] | zero | conv;
      all = all & done[v];
    }
    bool finished = true;
    for (int q = 0; q < W; ++q) finished = finished && all[q] != 0;
    if (finished) break;
  }
  for (int v = 0; v < NV; ++v) __builtin_memcpy(x.z + W * (v0 + v), &t[v], sizeof(V));
}
// The crossings from the columns' cubics (FitCrossings), on NV vectors of W lanes: each lane's own operations, the
// crossing into zq and whether it is certified into ok.
template <class V, int W, int NV>
__attribute__((always_inline)) inline void fit_interpolate_lanes(const FitCrossingSeries<V>& s, const FitCrossings& x,
                                                                 V* zq, typename MaskOf<V>::type* ok) {
  typedef typename MaskOf<V>::type M;
  const M sign = (M)(-V{});
  const V half = V{} + 0.5, one = V{} + 1.0, two = V{} + 2.0, sixth = V{} + 1.0 / 6.0;
  const V wd = V{} + x.width;
  for (int v = 0; v < NV; ++v) {
    V z0, z1, h0, h1, y, hf, bud, ua, v0, v1, v2, v3;
    __builtin_memcpy(&z0, x.z0 + W * v, sizeof(V));
    __builtin_memcpy(&z1, x.z1 + W * v, sizeof(V));
    __builtin_memcpy(&h0, x.h0 + W * v, sizeof(V));
    __builtin_memcpy(&h1, x.h1 + W * v, sizeof(V));
    __builtin_memcpy(&y, x.y + W * v, sizeof(V));
    __builtin_memcpy(&hf, x.hf + W * v, sizeof(V));
    __builtin_memcpy(&bud, x.bud + W * v, sizeof(V));
    __builtin_memcpy(&ua, x.ua + W * v, sizeof(V));
    __builtin_memcpy(&v0, x.v[0] + W * v, sizeof(V));
    __builtin_memcpy(&v1, x.v[1] + W * v, sizeof(V));
    __builtin_memcpy(&v2, x.v[2] + W * v, sizeof(V));
    __builtin_memcpy(&v3, x.v[3] + W * v, sizeof(V));
    // Newton's form on the nodes u = 0, 1, 2, 3: p(u) = v0 + u (d1 + (u - 1) (d2 / 2 + (u - 2) d3 / 6))
    const V e1 = v1 - v0, e2 = v2 - v1, d1 = e1, d2 = e2 - e1, d3 = ((v3 - v2) - e2) - d2;
    const V c2 = half * d2, c3 = sixth * d3;
    // (p'(u) = d1 + d2 (u - 1/2) + d3 (u^2 - 2u + 2/3) / 2; macros, as a lambda returning a vector would be compiled
    // without AVX)
#define POLARCAM_P(u) (v0 + (u) * (d1 + ((u)-one) * (c2 + ((u)-two) * c3)))
#define POLARCAM_DP(u) ((d1 + d2 * ((u)-half)) + c3 * (((V{} + 3.0) * (u) - (V{} + 6.0)) * (u) + two))
    const V ub = ua + one;
    V u = ua + (y - h0) / (h1 - h0);  // the chord's crossing
    u = u - (POLARCAM_P(u) - y) / POLARCAM_DP(u);
    const V res = POLARCAM_ABS(POLARCAM_P(u) - y);
#undef POLARCAM_P
#undef POLARCAM_DP
    // the derivative on the column: its part linear in u at the ends, less a bound on the rest (|u^2 - 2u + 2/3|
    // is at most 11/3 on [0, 3])
    const V la = d1 + d2 * (ua - half), lb = d1 + d2 * (ub - half), ala = POLARCAM_ABS(la), alb = POLARCAM_ABS(lb);
    const V rest = (V{} + 11.0 / 6.0) * POLARCAM_ABS(d3);
    const M lt = ala < alb;
    const V aw = POLARCAM_ABS(z1 - z0), per_z = one / aw, aw3 = aw * aw * aw;
    const V dh = (V{} + 27.0) * s.m4 * aw3;  // H' less the cubic's
    const V m1 = (POLARCAM_PICK(lt, ala, alb) - rest) * per_z - dh, mx = (POLARCAM_PICK(lt, alb, ala) + rest) * per_z + dh;
    // the node polynomial on the column: at most 9/16 w^4 on the middle one (u from 1 to 2), w^4 on the others
    const V node = POLARCAM_PICK(ua == one, V{} + 0.5625 / 24.0, V{} + 1.0 / 24.0);
    const V err = node * s.m4 * (aw3 * aw) + s.eps + (V{} + 0x1p-49) * mx + res;
    const M inside = (u > ua) & (u < ub);
    ok[v] = ((la > V{}) == (lb > V{})) & (m1 > V{}) & inside &
            ((hf * (wd * mx)) * (err * err) <= (bud * aw) * (m1 * m1));
    zq[v] = z0 + (u - ua) * (z1 - z0);
  }
}
// The cubics' crossings where certified (fit_interpolate_lanes); if a lane of the batch is not, the search on
// pairs of vectors (more side by side would not fit the processor's registers) for the batch, each lane then taking
// its own: a lane's crossing depends on its column alone. Then Astar's fit at the crossings on all NV vectors side
// by side (clenshaw_vectors).
template <class V, int W, int NV>
__attribute__((always_inline)) inline void fit_crossings_lanes(const FitCrossingSeries<V>& s, FitCrossings& x) {
  typedef typename MaskOf<V>::type M;
  V zq[NV];
  M ok[NV];
  fit_interpolate_lanes<V, W, NV>(s, x, zq, ok);
  uint32_t which = 0;
  for (int v = 0; v < NV; ++v)
    for (int q = 0; q < W; ++q) which |= static_cast<uint32_t>((ok[v][q] == 0) & (W * v + q < x.n)) << (W * v + q);
  x.searched_q = which;
  if (which != 0) {
    int v = 0;
    for (; v + 2 <= NV; v += 2) fit_search_lanes<V, W, 2>(s, x, v);
    if (v < NV) fit_search_lanes<V, W, 1>(s, x, v);
    for (v = 0; v < NV; ++v) {
      V zs;
      __builtin_memcpy(&zs, x.z + W * v, sizeof(V));
      zq[v] = POLARCAM_PICK(ok[v], zq[v], zs);
    }
  }
  for (int v = 0; v < NV; ++v) __builtin_memcpy(x.z + W * v, &zq[v], sizeof(V));
  clenshaw_vectors<V, W, NV>(s.a, s.na, x.z, x.a);
}
#undef POLARCAM_PICK
#undef POLARCAM_ABS

// The lanes after the batch's last column, up to the end of its last vector of W lanes, repeat it, so that no lane
// works on values that were never set.
inline void pad_crossings(FitCrossings& x, int W) {
  const int end = (x.n + W - 1) / W * W;
  for (int q = x.n; q < end; ++q) {
    x.z0[q] = x.z0[x.n - 1], x.z1[q] = x.z1[x.n - 1], x.h0[q] = x.h0[x.n - 1], x.h1[q] = x.h1[x.n - 1];
    x.y[q] = x.y[x.n - 1], x.ua[q] = x.ua[x.n - 1], x.hf[q] = x.hf[x.n - 1], x.bud[q] = x.bud[x.n - 1];
    for (int k = 0; k < 4; ++k) x.v[k][q] = x.v[k][x.n - 1];
  }
}

// The batch's crossings on as many vectors as it fills: of two lanes, or of four where the processor has AVX (the
// same values); the lanes after the last vector are left as they were. Astar's fit runs on all the batch's vectors
// side by side, which keeps the multipliers busy through its one chain of dependent steps.
inline void fit_crossings(const FitCrossingSeries<Lane2>& s, FitCrossings& x) {
  pad_crossings(x, 2);
  if (x.n <= 4)
    fit_crossings_lanes<Lane2, 2, 2>(s, x);
  else if (x.n <= 8)
    fit_crossings_lanes<Lane2, 2, 4>(s, x);
  else
    fit_crossings_lanes<Lane2, 2, 8>(s, x);
}

__attribute__((target("avx"))) inline void fit_crossings(const FitCrossingSeries<Lane4>& s, FitCrossings& x) {
  pad_crossings(x, 4);
  switch ((x.n + 3) / 4) {
    case 1:
      fit_crossings_lanes<Lane4, 4, 1>(s, x);
      break;
    case 2:
      fit_crossings_lanes<Lane4, 4, 2>(s, x);
      break;
    case 3:
      fit_crossings_lanes<Lane4, 4, 3>(s, x);
      break;
    default:
      fit_crossings_lanes<Lane4, 4, 4>(s, x);
  }
}

// The values of a series at the middles of the cnt - 1 columns between cnt >= 4 equally spaced points, from its
// values r at the points: the cubic through the four nearest points (the columns' own two and one on each side;
// the first and the last column the four at their end), weights (-1, 9, 9, -1) / 16 in the middle and
// (5, 15, -5, 1) / 16 at the ends. out[i] = base + (b + value).
inline void midpoint_values(const double* r, size_t cnt, double base, double b, double* out) {
  out[0] = base + (b + (5.0 * r[0] + 15.0 * r[1] - 5.0 * r[2] + r[3]) * 0.0625);
  for (size_t i = 1; i + 2 < cnt; ++i) out[i] = base + (b + (9.0 * (r[i] + r[i + 1]) - (r[i - 1] + r[i + 2])) * 0.0625);
  const size_t e = cnt - 4;
  out[cnt - 2] = base + (b + (r[e] - 5.0 * r[e + 1] + 15.0 * r[e + 2] + 5.0 * r[e + 3]) * 0.0625);
}
// A bound on the error of midpoint_values against the series H itself (b: its bounds), the points w apart in H's
// variable: the cubic's, M4 w^4 |node polynomial| / 4! with the node polynomial at most 15/16 w^4 (the end
// columns; 9/16 in the middle), the rounding of the values (weighted by at most 26/16) and of the points' places
// (a few units in the last place, times |H'|).
inline double midpoint_error(const SeriesBounds& b, double w) {
  const double w2 = w * w;
  return b.m4 * (w2 * w2) * (0.9375 / 24.0) + 1.625 * b.rounding + 0x1p-49 * b.m1;
}

// The nearest node to f (in units of the level spacing), fl = floor(f + 1/2); true where f is clear of a rounding
// boundary by margin + 1e-13 |f| and fl is a node (below 4e18 in magnitude). The nearest rule's test of the
// staircase read off the walk (StairAreaMeter::nearest_node, nearest_levels).
inline bool nearest_clear(double f, double margin, double& fl) {
  const double u = f + 0.5, m = margin + 1e-13 * std::abs(f);
  fl = std::floor(u);
  const double d = u - fl;
  return (std::abs(fl) < 4e18) & (d >= m) & (1.0 - d >= m);
}
// The nearest level of each of n radii h[i]: f = h[i] inv in units of the level spacing dr = 1 / inv, and rho[i] =
// floor(f + 1/2) dr. True where every f is clear (nearest_clear); false otherwise, and then rho is not to be used.
inline bool nearest_level(double h, double inv, double margin, double dr, double& rho) {
  double fl;
  const bool clear = nearest_clear(h * inv, margin, fl);
  rho = fl * dr;
  return clear;
}
inline bool nearest_levels(const double* h, size_t n, double inv, double margin, double dr, double* rho) {
  bool ok = true;
  for (size_t i = 0; i < n; ++i) ok &= nearest_level(h[i], inv, margin, dr, rho[i]);
  return ok;
}
// The same, four at a time with no branch where the processor has AVX (the same values: floor is exact, and no
// operation is fused).
__attribute__((target("avx"))) inline bool nearest_levels_avx(const double* h, size_t n, double inv, double margin,
                                                              double dr, double* rho) {
  typedef Lane4 V;
  typedef Mask4 M;
  const M sign = (M)(-V{});
  M bad = M{};
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    V hv;
    __builtin_memcpy(&hv, h + i, sizeof(V));
    const V f = hv * inv, u = f + 0.5, fl = __builtin_ia32_roundpd256(u, 1 /* toward minus infinity */), d = u - fl;
    const V af = (V)((M)f & ~sign), afl = (V)((M)fl & ~sign), m = margin + 1e-13 * af;
    bad |= ~((afl < 4e18) & (d >= m) & (1.0 - d >= m));
    const V r = fl * dr;
    __builtin_memcpy(rho + i, &r, sizeof(V));
  }
  bool ok = !(bad[0] | bad[1] | bad[2] | bad[3]);
  for (; i < n; ++i) ok &= nearest_level(h[i], inv, margin, dr, rho[i]);
  return ok;
}

}  // namespace polarcam::area_roots
