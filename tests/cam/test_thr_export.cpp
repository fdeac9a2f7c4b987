// Curves as theta-rho polylines (to_theta_rho): the tolerance checked against an independent dense comparison of
// the curve with the spirals the vertices stand for, vertex counts, exact cases, the pole.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <unordered_map>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/path.hpp"
#include "cam/thr_export.hpp"
#include "cam/toolpath.hpp"

namespace tu_cam_test_thr_export {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

constexpr double kPi = std::numbers::pi;

// Points along the theta-rho polyline, written here from the definition (x = rho cos theta, y = rho sin theta,
// theta and rho linear along each segment), at most `spacing` apart.
std::vector<Vec2> dense_spirals(const std::vector<ThetaRho>& v, double spacing) {
  std::vector<Vec2> out;
  for (size_t k = 0; k + 1 < v.size(); ++k) {
    const ThetaRho a = v[k], b = v[k + 1];
    const double bound = std::abs(b.rho - a.rho) + std::max(a.rho, b.rho) * std::abs(b.theta - a.theta);
    const int n = std::max(1, static_cast<int>(std::ceil(bound / spacing)));
    for (int i = 0; i <= n; ++i) {
      const double f = static_cast<double>(i) / n;
      const double th = a.theta + f * (b.theta - a.theta), rho = a.rho + f * (b.rho - a.rho);
      out.push_back({rho * std::cos(th), rho * std::sin(th)});
    }
  }
  return out;
}

// Points of the curve, uniform in its parameter, at most `spacing` apart (the count from the largest speed of a
// first sampling, doubled until they are).
std::vector<Vec2> dense_curve(const Curve& c, double spacing) {
  const double u0 = c.u_begin(), L = c.u_end() - c.u_begin();
  double speed = 0;
  for (int i = 0; i <= 4096; ++i) speed = std::max(speed, norm(c.eval(u0 + L * i / 4096, 1).d1));
  for (long n = std::max(4096L, std::lround(1.25 * speed * L / spacing));; n *= 2) {
    std::vector<Vec2> out;
    double gap = 0;
    for (long i = 0; i <= n; ++i) {
      out.push_back(c.eval(u0 + L * static_cast<double>(i) / static_cast<double>(n), 0).p);
      if (i > 0) gap = std::max(gap, norm(out[i] - out[i - 1]));
    }
    if (gap <= spacing) return out;
  }
}

// The largest distance from a point of `a` to the polyline `b` (its points at most a quarter of `tol` apart), by a
// grid of cells holding the polyline's pieces by their midpoints: a point with no piece in the nine cells about
// it counts as 1.5 tol away (enough to fail any check against tol).
double one_way(const std::vector<Vec2>& a, const std::vector<Vec2>& b, double tol) {
  const double cell = 1.5 * tol;
  auto key = [](int64_t i, int64_t j) { return (i << 32) ^ (j & 0xffffffff); };
  auto cell_of = [&](Vec2 p, int64_t& i, int64_t& j) {
    i = std::llround(std::floor(p.x / cell));
    j = std::llround(std::floor(p.y / cell));
  };
  std::unordered_map<int64_t, std::vector<size_t>> grid;
  for (size_t k = 0; k + 1 < b.size(); ++k) {
    int64_t i, j;
    cell_of(0.5 * (b[k] + b[k + 1]), i, j);
    grid[key(i, j)].push_back(k);
  }
  double worst = 0;
  std::vector<size_t> near;  // the pieces of the nine cells about (ci, cj): consecutive points share their cell
  int64_t ci = 0, cj = 0;
  bool have = false;
  for (Vec2 p : a) {
    int64_t i, j;
    cell_of(p, i, j);
    if (!have || i != ci || j != cj) {
      have = true, ci = i, cj = j;
      near.clear();
      for (int64_t di = -1; di <= 1; ++di)
        for (int64_t dj = -1; dj <= 1; ++dj) {
          auto it = grid.find(key(i + di, j + dj));
          if (it != grid.end()) near.insert(near.end(), it->second.begin(), it->second.end());
        }
    }
    // the squared distance to each piece, in plain arithmetic (the sanitized build, at -O1, calls every operator)
    const Vec2* bp = b.data();
    double d2 = cell * cell;
    for (size_t k : near) {
      const double ax = bp[k].x, ay = bp[k].y, ex = bp[k + 1].x - ax, ey = bp[k + 1].y - ay;
      const double wx = p.x - ax, wy = p.y - ay;
      double t = (wx * ex + wy * ey) / std::max(ex * ex + ey * ey, 1e-300);
      t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
      const double dx = wx - t * ex, dy = wy - t * ey, q = dx * dx + dy * dy;
      if (q < d2) d2 = q;
    }
    worst = std::max(worst, std::sqrt(d2));
  }
  return worst;
}

// The distance between the curve and the theta-rho polyline, both ways: from points a 25th of the tolerance apart
// on one to the other as a polyline of chords a quarter of the tolerance long (whose sagitta, below 1e-6 of the
// tolerance on these curves, is neglected). Between two points the distance changes by at most their spacing, so
// the true distance exceeds the one returned by at most a 50th of the tolerance: the checks ask for 0.98 of it.
double dense_distance(const Curve& c, const std::vector<ThetaRho>& v, double tol) {
  const double d = std::max(one_way(dense_curve(c, tol / 25), dense_spirals(v, tol / 4), tol),
                            one_way(dense_spirals(v, tol / 25), dense_curve(c, tol / 4), tol));
  std::printf("  distance %.4f of the tolerance\n", d / tol);
  return d;
}

// Theta continuous: no segment turns more than a quarter turn, except the arm turning at the centre.
void expect_continuous(const std::vector<ThetaRho>& v) {
  for (size_t k = 1; k < v.size(); ++k) {
    if (v[k].rho == 0.0 && v[k - 1].rho == 0.0) continue;
    EXPECT_LE(std::abs(v[k].theta - v[k - 1].theta), kPi / 2 + 1e-9) << "vertex " << k;
    EXPECT_FALSE(v[k].theta == v[k - 1].theta && v[k].rho == v[k - 1].rho) << "repeated vertex " << k;
  }
}

}  // namespace

TEST(ThrExport, ToleranceHoldsOnCurvesOffThePole) {
  const double tol = 1e-4;
  const Placement limacon_pole{0.0127, 0.0};  // the thesis's limacon example: C = 1.27 cm, beta = 0
  const Placement spiral_pole{0.006, 1.0};
  struct Case {
    const char* name;
    CurvePtr curve;
    size_t min_vertices, max_vertices;
  };
  // Counts measured (100 um tolerance): circle 47, line 47, limacon 47, spiral 62 (a circle of 30 mm radius as
  // chords would need 39). The bounds say "reasonable": within a factor of about two of these.
  const Case cases[] = {
      {"circle off the pole", make_circle({0.05, 0.02}, 0.03), 24, 94},
      {"line not through the pole", make_line({-0.1, 0.03}, {0.12, 0.05}), 24, 94},
      {"limacon", make_tool_path(make_limacon(0.0508, 0.0762), limacon_pole, {}, {}), 24, 94},
      {"spiral", make_tool_path(make_spiral(0.01, 0.005, 0, 20), spiral_pole, {}, {}), 31, 124},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const auto v = to_theta_rho(*c.curve, tol);
    std::printf("  %s: %zu vertices\n", c.name, v.size());
    EXPECT_GE(v.size(), c.min_vertices);
    EXPECT_LE(v.size(), c.max_vertices);
    EXPECT_LE(dense_distance(*c.curve, v, tol), 0.98 * tol);
    expect_continuous(v);
    // the ends are the curve's ends
    const Vec2 a = c.curve->eval(c.curve->u_begin(), 0).p, b = c.curve->eval(c.curve->u_end(), 0).p;
    EXPECT_NEAR(v.front().rho, norm(a), 1e-15);
    EXPECT_NEAR(v.back().rho, norm(b), 1e-15);
    EXPECT_NEAR(std::remainder(v.front().theta - std::atan2(a.y, a.x), 2 * kPi), 0.0, 1e-12);
    EXPECT_NEAR(std::remainder(v.back().theta - std::atan2(b.y, b.x), 2 * kPi), 0.0, 1e-12);
  }
}

TEST(ThrExport, ATighterToleranceNeedsMoreVerticesAndHolds) {
  const auto lim = make_tool_path(make_limacon(0.0508, 0.0762), {0.0127, 0.0}, {}, {});
  const auto coarse = to_theta_rho(*lim, 1e-3), fine = to_theta_rho(*lim, 4e-5);
  EXPECT_LT(coarse.size(), fine.size());
  EXPECT_LE(dense_distance(*lim, coarse, 1e-3), 0.98e-3);
  EXPECT_LE(dense_distance(*lim, fine, 4e-5), 0.98 * 4e-5);
  // a closed path about the pole winds once: its end is one turn from its start
  EXPECT_NEAR(fine.back().theta - fine.front().theta, 2 * kPi, 1e-12);
}

TEST(ThrExport, CircleAboutThePoleIsQuarterTurnsAtItsRadius) {
  const auto v = to_theta_rho(*make_circle({0, 0}, 0.04), 1e-6);
  ASSERT_EQ(v.size(), 5u);
  for (size_t k = 0; k < v.size(); ++k) {
    EXPECT_NEAR(v[k].rho, 0.04, 1e-16);
    EXPECT_NEAR(v[k].theta, k * kPi / 2, 1e-15);
  }
}

TEST(ThrExport, SpiralAboutThePoleIsExact) {
  // r = 0.01 + 0.005 t for t in [0, 20]: every segment of the polyline is a piece of this very spiral
  const auto v = to_theta_rho(*make_spiral(0.01, 0.005, 0, 20), 1e-6);
  EXPECT_EQ(v.size(), 17u);  // the parameter halved until no segment turns more than a quarter turn: 16 x 1.25 rad
  for (const ThetaRho& p : v) EXPECT_NEAR(p.rho, 0.01 + 0.005 * p.theta, 1e-15);
  EXPECT_NEAR(v.back().theta, 20.0, 1e-14);
}

TEST(ThrExport, ThetaRhoPathComesBackUnchanged) {
  const std::vector<ThetaRho> in{{0.0, 0.0}, {1.0, 0.01}, {7.5, 0.05}, {7.5, 0.02}, {-2.0, 0.03}};
  const auto path = make_theta_rho_path(in, "pattern");
  const auto out = to_theta_rho(*path, 1e-3);
  ASSERT_EQ(out.size(), in.size());
  for (size_t k = 0; k < in.size(); ++k) {
    EXPECT_EQ(out[k].theta, in[k].theta);
    EXPECT_EQ(out[k].rho, in[k].rho);
  }
}

TEST(ThrExport, LineThroughThePoleTurnsTheArmAtTheCentre) {
  // from (-0.05, -0.02) through the pole to (0.1, 0.04): arriving along theta0 + pi, leaving along theta0
  const double th0 = std::atan2(0.4, 1.0);
  const auto line = make_line({-0.05, -0.02}, {0.1, 0.04});
  const auto v = to_theta_rho(*line, 1e-4);
  ASSERT_EQ(v.size(), 4u);
  EXPECT_NEAR(v[0].rho, std::hypot(0.05, 0.02), 1e-15);
  EXPECT_NEAR(v[0].theta, th0 - kPi, 1e-12);
  EXPECT_EQ(v[1].rho, 0.0);
  EXPECT_NEAR(v[1].theta, th0 - kPi, 1e-9);
  EXPECT_EQ(v[2].rho, 0.0);
  EXPECT_NEAR(v[2].theta, v[1].theta + kPi, 1e-9);  // the half turn taken counter-clockwise
  EXPECT_NEAR(v[3].rho, std::hypot(0.1, 0.04), 1e-15);
  EXPECT_NEAR(v[3].theta, v[2].theta, 1e-9);
  EXPECT_LE(dense_distance(*line, v, 1e-4), 0.99e-4);
}

TEST(ThrExport, CurveThroughThePoleKeepsThetaContinuousOnEachSide) {
  // a circle through the pole: centre (30 mm, 0), radius 30 mm, u = 0 at (60 mm, 0), at the pole at u = pi, where
  // it arrives from above (theta -> pi/2) and leaves below (theta -> -pi/2 = 3 pi/2 after the half turn)
  const auto c = make_circle({0.03, 0.0}, 0.03);
  const auto v = to_theta_rho(*c, 1e-4);
  std::vector<size_t> at_pole;
  for (size_t k = 0; k < v.size(); ++k)
    if (v[k].rho == 0.0) at_pole.push_back(k);
  ASSERT_EQ(at_pole.size(), 2u);
  ASSERT_EQ(at_pole[1], at_pole[0] + 1);
  EXPECT_NEAR(v[at_pole[0]].theta, kPi / 2, 1e-9);
  EXPECT_NEAR(v[at_pole[1]].theta, 3 * kPi / 2, 1e-9);
  EXPECT_NEAR(v.front().theta, 0.0, 1e-15);
  EXPECT_NEAR(v.back().theta, 2 * kPi, 1e-12);
  expect_continuous(v);
  EXPECT_LE(dense_distance(*c, v, 1e-4), 0.99e-4);
}

TEST(ThrExport, RefusesABadTolerance) {
  const auto c = make_circle({0.05, 0.0}, 0.01);
  EXPECT_THROW(to_theta_rho(*c, 0.0), InputError);
  EXPECT_THROW(to_theta_rho(*c, -1e-3), InputError);
  EXPECT_THROW(to_theta_rho(*c, std::nan("")), InputError);
}

}  // namespace tu_cam_test_thr_export
