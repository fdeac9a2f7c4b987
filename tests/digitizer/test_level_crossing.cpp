// The level-crossing solver's fast forms against its plain one: the two-lane evaluations (eval_gs2,
// eval_gs_packed) must give bit for bit the values of eval_gs, the bound on the second derivative must hold, and
// the iteration-at-a-time solver (CrossingSolve, with the second derivatives asked for lazily or not) must give bit
// for bit the crossings of solve_crossing — the digitizer's tapes depend on it.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

#include "digitizer/level_crossing.hpp"

namespace tu_digitizer_test_level_crossing {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

uint64_t bits(double x) { return std::bit_cast<uint64_t>(x); }

// A series of degree `deg` with coefficients decaying like those of a smooth function (|c_k| ~ 2^-2k), random signs.
Cheb random_series(std::mt19937_64& rng, int deg, double scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Cheb c;
  c.deg = deg;
  for (int k = 0; k <= deg; ++k) c.c[k] = scale * u(rng) * std::ldexp(1.0, -2 * k);
  return c;
}

// eval_gs<true> on the values the lanes are compared with
void expect_same(const GS& a, const GS& b) {
  EXPECT_EQ(bits(a.g), bits(b.g));
  EXPECT_EQ(bits(a.g1), bits(b.g1));
  EXPECT_EQ(bits(a.g2), bits(b.g2));
  EXPECT_EQ(bits(a.s), bits(b.s));
  EXPECT_EQ(bits(a.s1), bits(b.s1));
  EXPECT_EQ(bits(a.s2), bits(b.s2));
}

}  // namespace

TEST(LevelCrossing, TwoLaneEvaluationsAreBitForBitThoseOfEvalGs) {
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> ut(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int d0 = 1 + trial % 16, d1 = 16 - trial % 13, ds = 2 + trial % 14;
    const Cheb g0 = random_series(rng, d0, 3e4), g1 = random_series(rng, d1, 7e3), S = random_series(rng, ds, 0.01);
    const int n0 = std::max(d0, ds), n1 = std::max(d1, ds);
    Lane2 cg[kChebMaxDegree + 1], cs[kChebMaxDegree + 1], p0[kChebMaxDegree + 1], p1[kChebMaxDegree + 1];
    for (int k = 0; k <= kChebMaxDegree; ++k) {
      cg[k] = Lane2{k <= n0 ? g0.c[k] : 0.0, k <= n1 ? g1.c[k] : 0.0};
      cs[k] = Lane2{k <= n0 ? S.c[k] : 0.0, k <= n1 ? S.c[k] : 0.0};
      p0[k] = Lane2{g0.c[k], S.c[k]};
      p1[k] = Lane2{g1.c[k], S.c[k]};
    }
    const double t0 = ut(rng), t1 = ut(rng);
    const GS r0 = eval_gs<true>(g0, S, t0), r1 = eval_gs<true>(g1, S, t1);
    const GS2 v = eval_gs2(cg, cs, std::max(n0, n1), Lane2{t0, t1});
    expect_same({v.g[0], v.g1[0], v.g2[0], v.s[0], v.s1[0], v.s2[0]}, r0);
    expect_same({v.g[1], v.g1[1], v.g2[1], v.s[1], v.s1[1], v.s2[1]}, r1);
    expect_same(eval_gs_packed(p0, n0, t0), r0);
    expect_same(eval_gs_packed(p1, n1, t1), r1);
    // without the second derivatives: the other values unchanged
    const GS q0 = eval_gs_packed<false>(p0, n0, t0);
    EXPECT_EQ(bits(q0.g), bits(r0.g));
    EXPECT_EQ(bits(q0.g1), bits(r0.g1));
    EXPECT_EQ(bits(q0.s), bits(r0.s));
    EXPECT_EQ(bits(q0.s1), bits(r0.s1));
    const GS2 w = eval_gs2<false>(cg, cs, std::max(n0, n1), Lane2{t0, t1});
    EXPECT_EQ(bits(w.g1[1]), bits(r1.g1));
    EXPECT_EQ(bits(w.s[1]), bits(r1.s));
  }
}

TEST(LevelCrossing, SecondDerivativeBoundHoldsAndIsTightForOnePolynomial) {
  // T_k alone: |T_k''| peaks at t = +-1 with k^2 (k^2 - 1) / 3, the bound's exact part
  for (int k = 0; k <= kChebMaxDegree; ++k) {
    double c[kChebMaxDegree + 1] = {};
    c[k] = 1.0;
    const double peak = k * k * (k * k - 1.0) / 3.0, b = second_derivative_bound(c, kChebMaxDegree);
    EXPECT_GE(b, peak);
    EXPECT_LE(b, peak + 1e-8 * (1.0 + std::pow(k, 4)) * 1.000001) << k;
  }
  // random series: the bound exceeds |g''| wherever it is evaluated
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Cheb g = random_series(rng, 4 + trial % 13, 1e5), S = random_series(rng, 3, 1.0);
    const double b = second_derivative_bound(g.c.data(), g.deg);
    for (int i = 0; i <= 400; ++i) {
      const double t = -1.0 + i / 200.0;
      EXPECT_LE(std::abs(eval_gs<true>(g, S, t).g2), b);
    }
  }
}

TEST(LevelCrossing, IterationAtATimeSolverGivesTheCrossingsOfSolveCrossing) {
  // a monotone g (in steps) and an arc length S over a piece: every level crossed, guesses extrapolated from the
  // previous three crossings as the step walker makes them
  Cheb g, S;
  g.deg = 12;
  S.deg = 13;
  for (int k = 0; k <= 13; ++k) {
    g.c[k] = k == 1 ? 5000.0 : (k <= 12 ? 300.0 * std::ldexp(1.0, -3 * k) * (k % 2 ? 1 : -1) : 0.0);
    S.c[k] = k == 1 ? 0.004 : 1e-4 * std::ldexp(1.0, -3 * k);
  }
  const double bg = second_derivative_bound(g.c.data(), 13), bs = second_derivative_bound(S.c.data(), 13);
  double hist[3] = {0, 0, 0}, lo = -1.0, flo = g(-1.0);
  const double fhi = g(1.0);
  int nh = 0, compared = 0;
  for (double level = std::floor(flo + 0.5) + 0.5; level < fhi; level += 1.0) {
    const double guess = nh >= 3 ? 3.0 * hist[0] - 3.0 * hist[1] + hist[2] : (nh >= 2 ? 2.0 * hist[0] - hist[1] : -2.0);
    const LevelCrossing want = solve_crossing<true>(g, S, level, lo, 1.0, flo - level, fhi - level, guess);
    // next() with all six values, and next_lazy() with the bounds
    CrossingSolve a, b;
    ASSERT_TRUE(a.start(S, level, lo, 1.0, flo - level, fhi - level, guess));
    ASSERT_TRUE(b.start(S, level, lo, 1.0, flo - level, fhi - level, guess));
    for (;;) {
      const GS v = eval_gs<true>(g, S, a.t);
      if (a.next(S, v.g, v.g1, v.g2, v.s, v.s1, v.s2)) break;
    }
    for (;;) {
      const GS v = eval_gs<true>(g, S, b.t);
      auto second = [&] { return std::pair<double, double>{v.g2, v.s2}; };
      if (b.next_lazy(S, v.g, v.g1, v.s, v.s1, bg, bs, second)) break;
    }
    ASSERT_EQ(bits(a.r.t), bits(want.t)) << level;
    ASSERT_EQ(bits(a.r.s), bits(want.s)) << level;
    ASSERT_EQ(bits(b.r.t), bits(want.t)) << level;
    ASSERT_EQ(bits(b.r.s), bits(want.s)) << level;
    // and the crossing is a root: g(t) at the level to a few units in the last place of g
    EXPECT_NEAR(g(want.t), level, 1e-10);
    hist[2] = hist[1];
    hist[1] = hist[0];
    hist[0] = want.t;
    nh = std::min(nh + 1, 3);
    lo = want.t;
    flo = level;
    ++compared;
  }
  EXPECT_GT(compared, 9000);
}

}  // namespace tu_digitizer_test_level_crossing
