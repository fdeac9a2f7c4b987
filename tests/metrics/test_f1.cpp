// The thesis's surrogate F_sum, F_dif, F1 (Eq. 4.5-4.15) and the deviation, against closed forms, quadrature and
// each other.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

#include "tests/area_helpers.hpp"
#include "cam/curves.hpp"
#include "metrics/error_metrics.hpp"
#include "metrics/f1.hpp"

namespace tu_metrics_test_f1 {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {

// integral of dtheta / r along the chord by composite Gauss-Legendre in long double (theta' = cross / |P|^2)
long double inv_r_quadrature(Vec2 a, Vec2 b) {
  const long double x[5] = {-0.9061798459386640L, -0.5384693101056831L, 0.0L, 0.5384693101056831L, 0.9061798459386640L};
  const long double w[5] = {0.2369268850561891L, 0.4786286704993665L, 0.5688888888888889L, 0.4786286704993665L,
                            0.2369268850561891L};
  const long double dx = (long double)b.x - a.x, dy = (long double)b.y - a.y;
  const long double c = (long double)a.x * dy - (long double)a.y * dx;
  const int n = 4000;
  long double sum = 0;
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < 5; ++i) {
      const long double s = (k + 0.5L + 0.5L * x[i]) / n;
      const long double px = a.x + s * dx, py = a.y + s * dy, r2 = px * px + py * py;
      sum += w[i] * 0.5L / n * c / (r2 * std::sqrt(r2));
    }
  return std::fabs(sum);
}

// The polar staircase of a run fed to a deviation meter, step by step (nodes from their indices; the reach of the
// foot search three cells).
void feed_polar_staircase(DeviationMeter& dm, const AreaRun& r, const Grid& g) {
  auto node = [&](double n, double m) {
    return Vec2{n * g.dr * std::cos(m * g.dtheta), n * g.dr * std::sin(m * g.dtheta)};
  };
  auto reach = [&](double n) { return 3.0 * std::max(g.dr, n * g.dr * g.dtheta) + 1e-12; };
  double n = static_cast<double>(r.dig.start_n), m = static_cast<double>(r.dig.start_m);
  dm.start(node(n, m), reach(n));
  for (const auto& s : r.steps) {
    StairPiece p;
    if (s.axis == kAxisRadial) {
      p.a = node(n, m);
      p.b = node(n + s.dir, m);
    } else {
      p.arc = true;
      p.rho = n * g.dr;
      p.phi0 = m * g.dtheta;
      p.phi1 = (m + s.dir) * g.dtheta;
      p.b = node(n, m + s.dir);
    }
    dm.piece(p, reach(s.axis == kAxisRadial ? n + 0.5 * s.dir : n));
    (s.axis == kAxisRadial ? n : m) += s.dir;
  }
}

}  // namespace

TEST(F1, ChordIntegralMatchesQuadrature) {
  struct C {
    Vec2 a, b;
  } cases[] = {
      {{0.10, 0.02}, {0.03, 0.12}},          // a general chord
      {{0.05, -0.03}, {0.05, 0.04}},         // passing the foot of the perpendicular
      {{0.08, 1e-7}, {0.20, 3e-7}},          // nearly radial: cancellation in the direct form
      {{-0.2, -0.1}, {-0.1000001, -0.05}},   // nearly radial, the other way
  };
  for (const auto& c : cases) {
    const double q = static_cast<double>(inv_r_quadrature(c.a, c.b));
    EXPECT_NEAR(chord_inverse_radius_integral(c.a, c.b), q, 1e-10 * q + 1e-18) << c.a.x << "," << c.a.y;
  }
}

// Eq. 4.7: a straight line along a ray, the pole beyond its end, has no angular steps: F_sum = F_dif = L / DeltaR.
TEST(F1, RadialLineFromCounts) {
  const double dr = 2.54e-5, dth = 2 * std::numbers::pi / 16000;
  std::vector<Vec2> pts{{0.10, 0}, {0.15, 0}, {0.20, 0}};
  std::vector<long long> nr{1969, 1968}, nt{0, 0};
  const F1Value v = f1_counts(pts, nr, nt, dr, dth);
  EXPECT_DOUBLE_EQ(v.F_sum, 3937.0);
  EXPECT_DOUBLE_EQ(v.F_dif, 3937.0);
  EXPECT_DOUBLE_EQ(v.F1, 1.0);
}

// The penalty K / R_m applies to segments where N_R > N_theta only (Eq. 4.5-4.6), R_m at the chord's midpoint.
TEST(F1, PenaltyFromCounts) {
  const double dr = 2.54e-5, dth = 2 * std::numbers::pi / 16000, K = dr / dth;  // K = 6.468 cm
  std::vector<Vec2> pts{{0.20, 0.0}, {0.20, 0.01}, {0.21, 0.01}};
  // segment 0: 20 radial, 100 angular (no penalty); segment 1: 300 radial, 40 angular (penalised)
  const F1Value v = f1_counts(pts, {20, 300}, {100, 40}, dr, dth);
  const double rm1 = std::hypot(0.205, 0.01), pen = 40 * K / rm1;
  EXPECT_NEAR(v.F_sum, (20 + 100) + (300 + pen), 1e-9);
  EXPECT_NEAR(v.F_dif, (100 - 20) + (300 - pen), 1e-9);
  EXPECT_NEAR(v.F1, v.F_dif / v.F_sum, 1e-15);
}

// Eq. 4.15 on chords: each chord contributes |dr|/DeltaR and |dtheta|/DeltaTheta, the latter penalised by
// (DeltaR/DeltaTheta^2) |int dtheta/r| where radial steps dominate. Checked on a hand-made two-chord path.
TEST(F1, ChordsByHand) {
  const double dr = 1e-4, dth = 1e-3;
  const Vec2 a{0.1, 0.0}, b{0.1, 0.005}, c{0.2, 0.006};
  const F1Value v = f1_chords({a, b, c}, dr, dth);
  // chord 1: mostly angular
  const double nr1 = std::abs(norm(b) - norm(a)) / dr, nt1 = std::atan2(cross(a, b), dot(a, b)) / dth;
  ASSERT_LT(nr1, nt1);
  // chord 2: mostly radial, penalised
  const double nr2 = (norm(c) - norm(b)) / dr, nt2 = std::abs(std::atan2(cross(b, c), dot(b, c))) / dth;
  ASSERT_GT(nr2, nt2);
  const double p2 = dr / (dth * dth) * static_cast<double>(inv_r_quadrature(b, c));
  EXPECT_NEAR(v.F_sum, nr1 + nt1 + nr2 + p2, 1e-9 * v.F_sum);
  EXPECT_NEAR(v.F_dif, (nt1 - nr1) + (nr2 - p2), 1e-9 * v.F_sum);
  EXPECT_EQ(v.segments_used, 2);
}

// Step counts per segment (any rule) and chords agree closely for a smooth contour: the two forms of F1 are the
// same quantity (Eq. 4.13), one counted and one integrated.
TEST(F1, CountsAgreeWithChords) {
  const Grid g = coarse_grid(0.0254e-3, 16000);
  auto path = make_tool_path(make_witch(0.2159, -0.2032, 0.2032), Placement{0.1546, 1.236}, ToolSpec{}, TravelSpec{});
  AreaRun r = area_run(*path, g, StepRule::nearest);
  ErrorMeters em;
  em.reset(*path, r.track, g, 40);
  for (const auto& s : r.steps) em.record(s.axis, s.dir);
  const ErrorMetrics m = em.finish(r.dig.start_n, r.dig.start_m);
  EXPECT_NEAR(m.area.area_m2, r.area.area_m2, 1e-15);
  EXPECT_NEAR(m.f_counts.F1, m.f_chords.F1, 0.01 * m.f_chords.F1);
  // every step is counted once
  EXPECT_NEAR(m.f_counts.F_sum + m.f_counts.F_dif, m.f_chords.F_sum + m.f_chords.F_dif, 0.02 * m.f_chords.F_sum);
  // deviation: the nearest rule keeps nodes within half a cell diagonal; the midpoints of steps stay within a cell
  const double rmax = r.track.r_max().value;
  EXPECT_GT(m.deviation_max_m, 0.25 * g.dr);
  EXPECT_LT(m.deviation_max_m, std::hypot(g.dr, rmax * g.dtheta));
  EXPECT_DOUBLE_EQ(m.deviation_eq41_m, rmax * g.dtheta);
}

// The deviation of a circle about the pole is exactly the radial offset of the node circle.
TEST(F1, DeviationOfACircleAboutThePole) {
  const Grid g = coarse_grid(1e-3, 720);
  const double R = 50.3e-3;
  auto path = make_tool_path(make_circle({0, 0}, R), Placement{}, ToolSpec{}, TravelSpec{});
  AreaRun r = area_run(*path, g, StepRule::nearest);
  ErrorMeters em;
  em.reset(*path, r.track, g, 10);
  for (const auto& s : r.steps) em.record(s.axis, s.dir);
  const ErrorMetrics m = em.finish(r.dig.start_n, r.dig.start_m);
  EXPECT_NEAR(m.deviation_max_m, R - 50e-3, 1e-12);
}

// The deviation samples a step's middle only where a bound on the distance inside the step (from its ends'
// distances, its length and the path's curvature at their feet) could beat the largest distance so far; the
// largest distance and its place are those of sampling every middle, and most middles are skipped.
TEST(F1, DeviationSkipsOnlyMiddlesThatCannotBeTheLargest) {
  struct Case {
    const char* name;
    ToolPathPtr path;
    Grid grid;
  };
  auto placed = [](CurvePtr c, double C, double beta) {
    return make_tool_path(std::move(c), Placement{C, beta}, ToolSpec{}, TravelSpec{});
  };
  const Grid thesis = coarse_grid(0.0254e-3, 16000);
  std::vector<Case> cases = {
      {"limacon", placed(make_limacon(0.0508, 0.0762), 0.0127, 0.0), thesis},
      {"witch", placed(make_witch(0.2159, -0.2032, 0.2032), 0.1546, 1.236), thesis},
      {"circle, pole outside", placed(make_circle({0, 0}, 0.0508), 0.2032, 1.5 * std::numbers::pi), thesis},
      {"serpentine near the pole", placed(make_serpentine(0.0127, 0.0762, -0.0762, 0.0762), 0.0537, 4.247), thesis},
      {"limacon, a grid ten times finer", placed(make_limacon(0.0508, 0.0762), 0.0127, 0.0),
       coarse_grid(0.00254e-3, 160000)},
  };
  for (const auto& c : cases) {
    const Grid& g = c.grid;
    AreaRun r = area_run(*c.path, g, StepRule::nearest);
    double dev[2];
    Vec2 at[2];
    uint64_t middles[2];
    for (int every = 0; every < 2; ++every) {
      DeviationMeter dm(*c.path);
      dm.set_every_middle(every == 1);
      feed_polar_staircase(dm, r, g);
      dev[every] = dm.max();
      at[every] = dm.at();
      middles[every] = dm.middles();
    }
    EXPECT_EQ(middles[1], r.steps.size()) << c.name;
    EXPECT_LT(middles[0] * 4, r.steps.size()) << c.name;
    EXPECT_GT(dev[0], 0.25 * g.dr) << c.name;
    // the same distance to the rounding of the path's coordinates, at the same place
    EXPECT_NEAR(dev[0], dev[1], 1e-9 * dev[1]) << c.name;
    EXPECT_NEAR(at[0].x, at[1].x, 1e-12) << c.name;
    EXPECT_NEAR(at[0].y, at[1].y, 1e-12) << c.name;
  }
}

}  // namespace tu_metrics_test_f1

namespace tu_metrics_test_f1 {

// Where the grid is fine enough for the deviation's local model, a node whose distance is bounded from above by a
// point of the model near it, by no more than the largest distance so far, is not searched for its foot: the
// largest distance and its place are those of searching every node (to the rounding of the path's coordinates, or
// at the mirror image of the place on these symmetric contours), and most nodes are bounded. The step counts of
// F1's segments (each step in the segment of its foot) are the same too.
TEST(F1, DeviationBoundsSkipOnlyNodesThatCannotBeTheLargest) {
  auto placed = [](CurvePtr c, double C, double beta) {
    return make_tool_path(std::move(c), Placement{C, beta}, ToolSpec{}, TravelSpec{});
  };
  struct Case {
    const char* name;
    ToolPathPtr path;
    Grid grid;
  };
  std::vector<Case> cases = {
      {"limacon, a grid 20 times finer", placed(make_limacon(0.0508, 0.0762), 0.0127, 0.0),
       coarse_grid(0.00127e-3, 320000)},
      {"witch's middle, a grid 50 times finer", placed(make_witch(0.2159, -0.05, 0.05), 0.1546, 1.236),
       coarse_grid(0.000508e-3, 800000)},
  };
  std::vector<AreaRun> runs;
  for (const auto& c : cases) {
    const Grid& g = c.grid;
    const AreaRun& r = runs.emplace_back(area_run(*c.path, g, StepRule::nearest));
    ErrorMetrics m[2];
    for (int bounds = 0; bounds < 2; ++bounds) {
      ErrorMeters em;
      em.reset(*c.path, r.track, g, 40);
      em.set_deviation_bounds(bounds == 1);
      for (const auto& s : r.steps) em.record(s.axis, s.dir);
      m[bounds] = em.finish(r.dig.start_n, r.dig.start_m);
    }
    EXPECT_GT(m[0].deviation_max_m, 0.25 * g.dr) << c.name;
    EXPECT_NEAR(m[1].deviation_max_m, m[0].deviation_max_m, 1e-9 * m[0].deviation_max_m) << c.name;
    const Vec2 a = m[0].deviation_at, b = m[1].deviation_at;
    const bool same = std::abs(a.x - b.x) < 1e-12 && std::abs(a.y - b.y) < 1e-12;
    const bool mirror = std::abs(std::abs(a.x) - std::abs(b.x)) < 1e-3 * g.dr &&
                        std::abs(std::abs(a.y) - std::abs(b.y)) < 1e-3 * g.dr;
    EXPECT_TRUE(same || mirror) << c.name << ": (" << a.x << ", " << a.y << ") and (" << b.x << ", " << b.y << ")";
    EXPECT_EQ(m[1].f_counts.F_sum, m[0].f_counts.F_sum) << c.name;
    EXPECT_EQ(m[1].f_counts.F_dif, m[0].f_counts.F_dif) << c.name;
    EXPECT_EQ(m[1].f_counts.F1, m[0].f_counts.F1) << c.name;
  }
  // the bounds are taken: most nodes of the finer witch are bounded, none with the bounds off
  const Grid& g = cases[1].grid;
  const AreaRun& r = runs[1];
  uint64_t bounded[2];
  for (int bounds = 0; bounds < 2; ++bounds) {
    DeviationMeter dm(*cases[1].path);
    dm.set_bounds(bounds == 1);
    feed_polar_staircase(dm, r, g);
    bounded[bounds] = dm.bounded();
  }
  EXPECT_EQ(bounded[0], 0u);
  EXPECT_GT(bounded[1] * 2, r.steps.size()) << bounded[1] << " of " << r.steps.size();
}

}  // namespace tu_metrics_test_f1

namespace tu_metrics_test_f1 {

// A foot's segment read from the segments' least parameters and the last segment's interval is the formula's,
// floor((u - u0) / (u1 - u0) n) clamped, for every parameter: at each boundary, one double either side of it, and
// at random parameters in a random order (the kept interval moving back and forth), on spans that straddle zero.
TEST(F1, SegmentOfAFootIsTheFormulasEverywhere) {
  uint64_t state = 99;
  auto uniform = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1.0p-53;  // [0, 1)
  };
  struct Span {
    double u0, u1;
    int n;
  };
  for (const Span& sp : {Span{0.0, 2.0 * std::numbers::pi, 100}, Span{-0.2032, 0.2032, 7}, Span{-3.0, -1.0, 1},
                         Span{0.1, 0.7, 1000}, Span{-1e-3, 5.0, 33}}) {
    SegmentIndex idx;
    idx.reset(sp.u0, sp.u1, sp.n);
    auto expected = [&](double u) {  // the formula, written out here
      const double x = std::floor((u - sp.u0) / (sp.u1 - sp.u0) * sp.n);
      return x <= 0.0 ? 0 : (x >= sp.n - 1 ? sp.n - 1 : static_cast<int>(x));
    };
    std::vector<double> us = {sp.u0, sp.u1, sp.u0 - 1.0, sp.u1 + 1.0, 0.0, -0.0};
    for (int i = 1; i < sp.n; ++i) {  // about each nominal boundary, and one double either side of its exact one
      const double b = sp.u0 + (sp.u1 - sp.u0) * i / sp.n;
      double lo = std::nextafter(b, -INFINITY), hi = b;
      for (int k = 0; k < 8; ++k) lo = std::nextafter(lo, -INFINITY), hi = std::nextafter(hi, INFINITY);
      for (double u = lo; u <= hi; u = std::nextafter(u, INFINITY)) us.push_back(u);
    }
    for (int k = 0; k < 2000; ++k) us.push_back(sp.u0 + (sp.u1 - sp.u0) * (1.2 * uniform() - 0.1));
    for (size_t k = us.size(); k > 1; --k) std::swap(us[k - 1], us[static_cast<size_t>(uniform() * k)]);
    int changes = 0, last = -1;
    for (double u : us) {
      const int got = idx.of(u);
      EXPECT_EQ(got, expected(u)) << "u = " << u << " on [" << sp.u0 << ", " << sp.u1 << "] / " << sp.n;
      EXPECT_EQ(got, idx.formula(u));
      changes += got != last;
      last = got;
    }
    if (sp.n > 1) {
      EXPECT_GT(changes, 100);  // the kept interval was left and found again many times
    }
  }
}

}  // namespace tu_metrics_test_f1
