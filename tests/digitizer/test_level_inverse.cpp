// The digitizer's inverse (level_inverse.hpp, walk_sub_interval_inverse): the arc length at a level as a
// certified polynomial of the level. Checked against crossings found by plain bisection, and the walker's steps
// against those of the crossing-by-crossing solver on the tracks of several contours (the steps, axes,
// directions and order the same, every arc length within the tolerance), including pieces where the fit is
// refused and the crossings are solved one by one, and sub-intervals walked in halves for their number of levels.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "cam/curves.hpp"
#include "cam/spline.hpp"
#include "cam/toolpath.hpp"
#include "digitizer/level_inverse.hpp"
#include "digitizer/polar_track.hpp"
#include "digitizer/step_walker.hpp"

namespace tu_digitizer_test_level_inverse {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

// t in [lo, hi] where the increasing or decreasing g reaches y, by bisection to the last bit (no derivative, no guess)
double bisect(const Cheb& g, double y, double lo, double hi) {
  const bool up = g(hi) > g(lo);
  for (int it = 0; it < 2000; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (!(mid > lo && mid < hi)) break;
    ((g(mid) < y) == up ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

void pack(const Cheb& g, const Cheb& S, Lane2* pk) {
  for (int k = 0; k <= kChebMaxDegree; ++k) pk[k] = Lane2{g.c[k], S.c[k]};
}

// a monotone g (in steps, about 5000 over [-1, 1]) and an arc length S, with smooth random perturbations
void random_piece(std::mt19937_64& rng, Cheb& g, Cheb& S) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  g = Cheb{};
  S = Cheb{};
  g.deg = S.deg = 14;
  for (int k = 0; k <= 14; ++k) {
    g.c[k] = (k == 1 ? 5000.0 : 0.0) + 400.0 * u(rng) * std::ldexp(1.0, -3 * k);
    S.c[k] = (k == 1 ? 0.004 : 0.0) + 2e-4 * u(rng) * std::ldexp(1.0, -3 * k);
  }
}

}  // namespace

TEST(LevelInverse, ArcLengthAtLevelsMatchesBisection) {
  std::mt19937_64 rng(20261201);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double tol = 1e-14;  // m, on an arc length of about 8 mm
  int accepted = 0, checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Cheb g, S;
    random_piece(rng, g, S);
    Lane2 pk[kChebMaxDegree + 1];
    pack(g, S, pk);
    double ta = u(rng), tb = u(rng);
    if (ta > tb) std::swap(ta, tb);
    if (trial % 4 == 0) ta = -1.0, tb = 1.0;
    if (tb - ta < 0.05) continue;
    LevelInverse inv;
    if (!fit_level_inverse(pk, 14, ta, tb, tol, inv)) continue;
    ++accepted;
    const double ya = g(ta), yb = g(tb);
    for (int i = 0; i <= 500; ++i) {
      const double y = ya + (yb - ya) * (i + 0.37) / 501.0;
      const double t = bisect(g, y, ta, tb);
      ASSERT_NEAR(inv(y), S(t), tol) << "trial " << trial << " y " << y;
      ++checked;
    }
  }
  EXPECT_GE(accepted, 25);
  EXPECT_GT(checked, 10000);
}

TEST(LevelInverse, RefusedWhereTheCoordinateTurns) {
  // g = 1000 (t + 1)^2 has g' = 0 at t = -1: the arc length as a function of the level has a square-root
  // singularity there, and no polynomial of degree 16 is within 1e-14 of it
  Cheb g, S;
  g.deg = 2;
  g.c[0] = 1500.0;  // 1000 (t + 1)^2 = 1000 (t^2 + 2t + 1) = 500 T2 + 2000 T1 + 1500 T0
  g.c[1] = 2000.0;
  g.c[2] = 500.0;
  S.deg = 1;
  S.c[1] = 0.004;
  Lane2 pk[kChebMaxDegree + 1];
  pack(g, S, pk);
  LevelInverse inv;
  EXPECT_FALSE(fit_level_inverse(pk, 2, -1.0, 1.0, 1e-14, inv));
  // away from the turn the same coordinate is fitted, and right
  ASSERT_TRUE(fit_level_inverse(pk, 2, 0.6, 1.0, 1e-14, inv));
  for (double y = 2561.0; y < 3999.0; y += 7.3) EXPECT_NEAR(inv(y), S(bisect(g, y, 0.6, 1.0)), 1e-14);
  // a coordinate that is not monotone on the interval is refused
  EXPECT_FALSE(fit_level_inverse(pk, 2, -1.5, 1.0, 1e-14, inv));
}

namespace {

struct StepRec {
  int axis, dir;
  double s;
};
struct PlainEmit {
  std::vector<StepRec>* out;
  void operator()(int a, int d, double s) { out->push_back({a, d, s}); }
};
struct InverseEmit {
  std::vector<StepRec>* out;
  double tol;
  double arc_tolerance(double, double) const { return tol; }
  void operator()(int a, int d, double s) { out->push_back({a, d, s}); }
};

struct Contour {
  const char* name;
  CurvePtr curve;
  Placement pl;
};

// The steps of the track from its nearest start node; end: the nodes at the end.
std::vector<StepRec> walk(const PolarTrack& tr, double dr, double dth, double tol, int64_t end[2]) {
  WalkGrid wg;
  wg.res[0] = dr;
  wg.res[1] = dth;
  wg.h = 0.5;
  const TrackPiece& p0 = tr.pieces().front();
  int64_t node[2] = {static_cast<int64_t>(std::floor(p0.q_a[0] / dr + 0.5)),
                     static_cast<int64_t>(std::floor(p0.q_a[1] / dth + 0.5))};
  std::vector<StepRec> out;
  if (tol > 0) {
    InverseEmit e{&out, tol};
    walk_steps<true, WalkStyle<true, 3>>(tr, wg, node, e);
  } else {
    PlainEmit e{&out};
    walk_steps<true, WalkStyle<true, 3>>(tr, wg, node, e);
  }
  end[0] = node[0];
  end[1] = node[1];
  return out;
}

}  // namespace

TEST(LevelInverse, WalkerGivesTheStepsOfTheCrossingSolver) {
  std::vector<Vec2> pts;
  for (int i = 0; i < 60; ++i) {
    const double t = 2 * std::numbers::pi * i / 60, r = 0.0762 + 0.0508 * std::cos(t) + 0.004 * std::sin(7 * t);
    pts.push_back({r * std::cos(t), r * std::sin(t)});
  }
  const double dr = 0.0000254, dth = 2 * std::numbers::pi / 16000;
  // the circle's largest radius 0.5 nm beyond the level r = (n + 1/2) dr: a crossing pair at a near-tangency
  const double tangent_c = (std::floor(0.1 / dr) + 0.5) * dr + 5e-10 - 0.03;
  const std::vector<Contour> cs = {
      {"limacon", make_limacon(0.0508, 0.0762), {0.0127, 0.0}},
      {"limacon_off_pole", make_limacon(0.0508, 0.0762), {0.1778, 3 * std::numbers::pi / 4}},
      {"witch", make_witch(0.2159, -0.2032, 0.2032), {0.1546, 1.236}},
      {"spline", make_spline(pts, true, "test"), {0.0127, 0.0}},
      {"circle_about_pole", make_circle({0, 0}, 0.0508), {0.0, 0.0}},
      {"circle_off_pole", make_circle({0, 0}, 0.0508), {0.2032, 3 * std::numbers::pi / 2}},
      {"circle_near_tangent", make_circle({0, 0}, 0.03), {tangent_c, std::numbers::pi}},
  };
  const double tol = 1.52e-14;  // 1 ps at 1.52 cm/s
  InverseScratch& st = inverse_scratch();
  const uint64_t fitted0 = st.fitted_levels, solved0 = st.solved_levels, refused0 = st.refused, halves0 = st.halves;
  for (const auto& c : cs) {
    for (double finer : {1.0, 10.0, 100.0}) {
      if (finer == 100.0 && std::string(c.name) != "limacon") continue;  // over 2^14 levels a sub-interval: halves
      SCOPED_TRACE(std::string(c.name) + " x" + std::to_string(finer));
      auto path = make_tool_path(c.curve, c.pl, ToolSpec{}, TravelSpec{});
      const PolarTrack tr = PolarTrack::build(*path);
      int64_t e0[2], e1[2];
      const auto want = walk(tr, dr / finer, dth / finer, 0.0, e0);
      const auto got = walk(tr, dr / finer, dth / finer, tol, e1);
      ASSERT_EQ(got.size(), want.size());
      EXPECT_EQ(e1[0], e0[0]);
      EXPECT_EQ(e1[1], e0[1]);
      double worst = 0;
      for (size_t i = 0; i < want.size(); ++i) {
        ASSERT_EQ(got[i].axis, want[i].axis) << "step " << i;
        ASSERT_EQ(got[i].dir, want[i].dir) << "step " << i;
        worst = std::max(worst, std::abs(got[i].s - want[i].s));
      }
      EXPECT_LE(worst, tol) << "largest arc-length difference, m";
    }
  }
  // both ways of timing ran: levels timed by fits, fits refused, and levels solved one by one
  EXPECT_GT(st.fitted_levels - fitted0, 100000u);
  EXPECT_GT(st.solved_levels - solved0, 1000u);
  EXPECT_GT(st.refused - refused0, 10u);
  EXPECT_GT(st.halves - halves0, 10u);
}

TEST(LevelInverse, TiedAndNearlyTiedCrossingsKeepTheSolversOrder) {
  // one piece whose two axes are the same coordinate (every crossing of axis 0 at the same point as one of axis
  // 1: axis 0 first), then axis 1 ahead by 1e-9 of a step (its crossings 1e-12 earlier in t, closer in arc length
  // than the fits can order: each pair is ordered by solving both crossings)
  for (double ahead : {0.0, 1e-15}) {
    SCOPED_TRACE(ahead);
    TrackPiece pc;
    pc.ua = 0;
    pc.ub = 1;
    for (int a = 0; a < 2; ++a) {
      pc.Q[a].deg = 3;
      pc.Q[a].c[0] = 0.0002;
      pc.Q[a].c[1] = 0.001;
      pc.Q[a].c[2] = 0.0002;
      pc.Q[a].c[3] = 0.00005;
      pc.q_a[a] = 0.05 + (a == 1 ? ahead : 0.0) + 0.4e-6;
      pc.q_b[a] = pc.q_a[a] + pc.Q[a](1.0);
    }
    pc.Q[0].c[0] = pc.Q[1].c[0] = -(pc.Q[0].c[1] * -1.0 + pc.Q[0].c[2] * 1.0 + pc.Q[0].c[3] * -1.0);  // Q(-1) = 0
    for (int a = 0; a < 2; ++a) pc.q_b[a] = pc.q_a[a] + pc.Q[a](1.0);
    pc.S.deg = 1;
    pc.S.c[0] = pc.S.c[1] = 0.002;
    pc.len = pc.S(1.0);
    WalkGrid wg;
    wg.res[0] = wg.res[1] = 1e-6;
    std::vector<StepRec> want, got;
    std::vector<double> ts;
    int64_t n0[2] = {50000, 50000}, n1[2] = {50000, 50000};
    PlainEmit pe{&want};
    walk_piece<true, WalkStyle<true, 3>>(pc, nullptr, 0, false, wg, n0, pe, ts);
    InverseScratch& st = inverse_scratch();
    const uint64_t ties0 = st.ties, fitted0 = st.fitted_levels;
    InverseEmit ie{&got, 1.52e-14};
    walk_piece<true, WalkStyle<true, 3>>(pc, nullptr, 0, false, wg, n1, ie, ts);
    EXPECT_GT(st.fitted_levels - fitted0, 2000u);
    EXPECT_GT(st.ties - ties0, 1000u);
    ASSERT_GT(want.size(), 2000u);
    ASSERT_EQ(got.size(), want.size());
    EXPECT_EQ(n1[0], n0[0]);
    EXPECT_EQ(n1[1], n0[1]);
    for (size_t i = 0; i < want.size(); ++i) {
      ASSERT_EQ(got[i].axis, want[i].axis) << "step " << i;
      ASSERT_EQ(got[i].dir, want[i].dir) << "step " << i;
      ASSERT_NEAR(got[i].s, want[i].s, 1.52e-14) << "step " << i;
    }
    // the order itself: axis 0 first at a tie, axis 1 first when it is ahead
    EXPECT_EQ(want[0].axis, ahead == 0.0 ? 0 : 1);
  }
}

// The fit's check evaluates its series at the halfway points on the lanes of vectors (cheb_values): every value must be
// Cheb::operator()'s to the bit, for every degree and however many points (full groups of eight, pairs, one left).
TEST(LevelInverse, ValuesOnLanesAreTheSeriesBitForBit) {
  std::mt19937_64 rng(20261208);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int deg = 0; deg <= kChebMaxDegree; ++deg)
    for (int n = 1; n <= 19; ++n) {
      Cheb s;
      s.deg = deg;
      for (int k = 0; k <= deg; ++k) s.c[static_cast<size_t>(k)] = u(rng) * std::pow(0.3, k) * 1e3;
      std::vector<double> z(static_cast<size_t>(n)), out(static_cast<size_t>(n), -7.0);
      for (auto& v : z) v = u(rng);
      z[0] = 1.0;
      z[static_cast<size_t>(n) - 1] = n > 1 ? -1.0 : z[0];
      cheb_values(s, z.data(), n, out.data());
      for (int i = 0; i < n; ++i) {
        const double want = s(z[static_cast<size_t>(i)]);
        EXPECT_EQ(std::memcmp(&want, &out[static_cast<size_t>(i)], sizeof(double)), 0)
            << "degree " << deg << ", point " << i << " of " << n << ": " << out[static_cast<size_t>(i)] << " vs "
            << want;
      }
    }
}

}  // namespace tu_digitizer_test_level_inverse
