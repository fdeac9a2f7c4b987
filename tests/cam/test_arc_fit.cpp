// Lines-and-arcs approximation (cam/arc_fit.hpp): exact on circles and polygons, within the chord tolerance on
// smooth curves as measured by an independent dense check, continuous, and refusing impossible tolerances.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/arc_fit.hpp"
#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/path.hpp"

namespace tu_cam_test_arc_fit {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

constexpr double kPi = std::numbers::pi;

// Distance from p to a segment, written independently of cam/arc_fit.cpp: an arc is tested by the angle of p
// from the centre measured along the arc's direction with fmod.
double dist(const PathSegment& s, Vec2 p) {
  if (s.kind == PathSegment::Kind::line) {
    const double L = norm(s.to - s.from);
    const Vec2 u = (s.to - s.from) / L;
    const double t = std::min(std::max(dot(p - s.from, u), 0.0), L);
    return norm(p - (s.from + u * t));
  }
  const double R = norm(s.from - s.center);
  const double a0 = std::atan2(s.from.y - s.center.y, s.from.x - s.center.x);
  const double ap = std::atan2(p.y - s.center.y, p.x - s.center.x);
  double along = std::fmod((s.sweep > 0 ? ap - a0 : a0 - ap) + 4 * kPi, 2 * kPi);
  if (along <= std::abs(s.sweep) + 1e-15) return std::abs(norm(p - s.center) - R);
  return std::min(norm(p - s.from), norm(p - s.to));
}

// Largest distance from the curve (dense samples) to the nearest segment of the fit.
double dense_deviation(const Curve& c, const std::vector<PathSegment>& segs, int samples) {
  double worst = 0;
  for (int i = 0; i <= samples; ++i) {
    const Vec2 p = c.eval(c.u_begin() + (c.u_end() - c.u_begin()) * i / samples, 0).p;
    double best = 1e300;
    for (const auto& s : segs) best = std::min(best, dist(s, p));
    worst = std::max(worst, best);
  }
  return worst;
}

void expect_chained(const Curve& c, const ArcFit& f) {
  ASSERT_FALSE(f.segments.empty());
  EXPECT_EQ(f.segments.front().from, c.eval(c.u_begin(), 0).p);
  for (size_t i = 0; i + 1 < f.segments.size(); ++i) EXPECT_EQ(f.segments[i].to, f.segments[i + 1].from) << i;
  if (c.closed()) {
    EXPECT_EQ(f.segments.back().to, f.segments.front().from);
  }
  for (const auto& s : f.segments) {
    if (s.kind != PathSegment::Kind::arc) continue;
    EXPECT_LE(std::abs(s.sweep), kPi / 2 * (1 + 1e-9));
    EXPECT_NEAR(norm(s.to - s.center), norm(s.from - s.center), 1e-12 * norm(s.from - s.center));
  }
}

// The fit of `c` to `tolerance`, checked to be one chain of segments.
ArcFit fit_chained(const Curve& c, double tolerance) {
  ArcFitOptions o;
  o.tolerance = tolerance;
  ArcFit f = fit_lines_and_arcs(c, o);
  expect_chained(c, f);
  return f;
}

}  // namespace

TEST(ArcFit, CircleIsFourExactQuarterArcs) {
  auto c = make_circle({0.15, 0.1}, 0.05);
  ArcFit f = fit_chained(*c, 1e-6);
  ASSERT_EQ(f.arcs, 4u);
  EXPECT_EQ(f.lines, 0u);
  for (const auto& s : f.segments) {
    EXPECT_NEAR(s.center.x, 0.15, 1e-15);
    EXPECT_NEAR(s.center.y, 0.1, 1e-15);
    EXPECT_NEAR(norm(s.from - s.center), 0.05, 1e-15);
    EXPECT_NEAR(s.sweep, kPi / 2, 1e-12);
  }
  EXPECT_LT(f.max_deviation, 1e-15);
}

TEST(ArcFit, PolygonIsItsLines) {
  std::vector<PathSegment> sq;
  const Vec2 v[4] = {{0.1, 0.05}, {0.2, 0.05}, {0.2, 0.15}, {0.1, 0.15}};
  for (int i = 0; i < 4; ++i) {
    PathSegment s;
    s.from = v[i];
    s.to = v[(i + 1) % 4];
    sq.push_back(s);
  }
  auto c = make_path(sq, true);
  ArcFit f = fit_chained(*c, 1e-7);
  ASSERT_EQ(f.lines, 4u);
  EXPECT_EQ(f.arcs, 0u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(f.segments[i].from.x, v[i].x, 1e-15);
    EXPECT_NEAR(f.segments[i].from.y, v[i].y, 1e-15);
  }
}

TEST(ArcFit, SmoothCurvesStayWithinTheTolerance) {
  struct Case {
    CurvePtr c;
    double tol;
  };
  const Case cases[] = {{make_limacon(0.0508, 0.0762), 6.35e-6},
                        {make_limacon(0.0508, 0.0762), 1e-7},
                        {make_witch(0.2159, -0.2032, 0.2032), 6.35e-6},
                        {make_serpentine(0.0127, 0.0762, -0.0762, 0.0762), 2e-6},
                        {make_rose(0.05, 3, 1), 1e-5}};
  for (const auto& k : cases) {
    SCOPED_TRACE(k.c->name() + " tol " + std::to_string(k.tol));
    ArcFit f = fit_chained(*k.c, k.tol);
    EXPECT_LE(f.max_deviation, k.tol);
    const double dense = dense_deviation(*k.c, f.segments, 6000);
    EXPECT_LE(dense, k.tol * (1 + 1e-9));
    // the reported deviation is the real one, not a loose bound
    EXPECT_GE(f.max_deviation, 0.5 * dense);
    // arcs do the work: far fewer segments than lines alone would need at this tolerance
    EXPECT_GT(f.arcs, f.lines);
  }
}

TEST(ArcFit, FinerToleranceNeedsMoreSegments) {
  auto c = make_limacon(0.0508, 0.0762);
  ArcFitOptions coarse, fine;
  coarse.tolerance = 1e-5;
  fine.tolerance = 1e-7;
  EXPECT_LT(fit_lines_and_arcs(*c, coarse).segments.size(), fit_lines_and_arcs(*c, fine).segments.size());
}

TEST(ArcFit, RefusesBadTolerances) {
  auto c = make_limacon(0.0508, 0.0762);
  ArcFitOptions o;
  o.tolerance = 0.0;
  EXPECT_THROW(fit_lines_and_arcs(*c, o), InputError);
  o.tolerance = std::nan("");
  EXPECT_THROW(fit_lines_and_arcs(*c, o), InputError);
  o.tolerance = 1e-9;
  o.max_segments = 50;  // the limacon needs hundreds at 1 nm
  EXPECT_THROW(fit_lines_and_arcs(*c, o), InputError);
}

}  // namespace tu_cam_test_arc_fit
