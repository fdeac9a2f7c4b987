// The error metrics of a Cartesian staircase (metrics/cartesian_error.hpp) against closed forms, an exact CGAL
// arrangement (metrics/area_check.hpp) and the strip meter's own general sweep:
//  - an axis-aligned rectangle: the staircase is the rectangle of the nearest nodes, the area error the area of
//    the symmetric difference of the two rectangles, the deviation the largest distance from the node rectangle's
//    outline to the path's, found here by brute force;
//  - 45-degree lines through and beside the nodes: triangles of known area;
//  - polygons and a circle stepped at exact times and by the DDA: the area against CGAL, the deviation of the
//    circle against its closed form ||p| - R| on every unit segment.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/path.hpp"
#include "tests/helpers.hpp"
#include "machine/cartesian/cartesian_exact.hpp"
#include "machine/cartesian/dda.hpp"
#include "metrics/area_check.hpp"
#include "metrics/cartesian_error.hpp"
#include "metrics/deviation.hpp"

namespace tu_metrics_test_cartesian_error {  // the test files of a program compile together (unity build)

using namespace polarcam;
using polarcam::test::outline_deviation;
using polarcam::test::RecordingSink;

namespace {

constexpr double kPi = std::numbers::pi;

struct XYRun {
  CartesianTrack track;
  CartesianResult res;
  std::vector<test::Recorded> steps;
  CartesianErrorMetrics m;
  CartesianAreaResult general;  // the same area by the general sweep only
};

CartesianErrorMetrics measure(const Curve& path, const CartesianTrack& track, double blu,
                              const std::vector<test::Recorded>& steps, const int64_t start[2]) {
  CartesianErrorMeters em;
  em.reset(path, track, blu);
  for (const auto& s : steps) em.record(s.axis, s.dir);
  return em.finish(start[0], start[1]);
}

XYRun exact_run(const Curve& path, double blu) {
  XYRun r;
  r.track = CartesianTrack::build(path);
  auto prof = make_constant_speed(0.02, r.track.length());
  RecordingSink rec;
  r.res = step_exact(r.track, blu, *prof, &rec);
  r.steps = rec.steps;
  r.m = measure(path, r.track, blu, r.steps, r.res.start);
  CartesianAreaMeter g;
  g.reset(r.track, blu);
  g.set_force_general(true);
  for (const auto& s : r.steps) g.record(s.axis, s.dir);
  r.general = g.finish(r.res.start[0], r.res.start[1]);
  return r;
}

std::vector<XYNode> nodes_of(const int64_t start[2], const std::vector<test::Recorded>& steps) {
  std::vector<XYNode> v{{start[0], start[1]}};
  for (const auto& s : steps) {
    XYNode x = v.back();
    (s.axis == kAxisX ? x.i : x.j) += s.dir;
    v.push_back(x);
  }
  return v;
}

CurvePtr polygon(const std::vector<Vec2>& v) {
  std::vector<PathSegment> segs;
  for (size_t i = 0; i < v.size(); ++i) segs.push_back({PathSegment::Kind::line, v[i], v[(i + 1) % v.size()], {}, 0});
  return make_path(segs, true);
}


}  // namespace

// An axis-aligned rectangle from (x0, y0) to (x1, y1): the exact generator's staircase runs along the nearest
// nodes, i.e. round(x0) .. round(x1) by round(y0) .. round(y1); the cycle is the two outlines, one inside the
// other or crossing, and the area error is |A| + |B| - 2 |A n B|.
TEST(CartesianError, AxisAlignedRectangleIsASymmetricDifference) {
  const double blu = 0.1e-3;
  struct Rect {
    double x0, y0, x1, y1;  // in BLU
  };
  for (const Rect& q : {Rect{0.3, 0.3, 10.3, 10.3}, Rect{-3.2, 4.7, 17.4, 12.6}, Rect{5.45, -8.8, 31.05, -2.3}}) {
    auto path = polygon({{q.x0 * blu, q.y0 * blu}, {q.x1 * blu, q.y0 * blu}, {q.x1 * blu, q.y1 * blu}, {q.x0 * blu, q.y1 * blu}});
    XYRun r = exact_run(*path, blu);
    const double X0 = std::floor(q.x0 + 0.5), X1 = std::floor(q.x1 + 0.5), Y0 = std::floor(q.y0 + 0.5),
                 Y1 = std::floor(q.y1 + 0.5);
    const double A = (q.x1 - q.x0) * (q.y1 - q.y0), B = (X1 - X0) * (Y1 - Y0);
    const double I = std::max(0.0, std::min(q.x1, X1) - std::max(q.x0, X0)) *
                     std::max(0.0, std::min(q.y1, Y1) - std::max(q.y0, Y0));
    const double expect = (A + B - 2 * I) * blu * blu;
    EXPECT_TRUE(r.res.returns_to_start);
    EXPECT_EQ(r.m.area.run_steps, static_cast<uint64_t>(2 * (X1 - X0)));
    EXPECT_EQ(r.m.area.rise_steps, static_cast<uint64_t>(2 * (Y1 - Y0)));
    EXPECT_NEAR(r.m.area.area_m2, expect, 1e-12 * expect) << q.x0;
    EXPECT_NEAR(r.general.area_m2, expect, 1e-12 * expect) << q.x0;

    // deviation: the largest distance from the node rectangle's outline to the path's, by brute force
    const Vec2 P[4] = {{q.x0, q.y0}, {q.x1, q.y0}, {q.x1, q.y1}, {q.x0, q.y1}};
    const Vec2 S[4] = {{X0, Y0}, {X1, Y0}, {X1, Y1}, {X0, Y1}};
    const double dmax = outline_deviation(S, P);
    EXPECT_NEAR(r.m.deviation_max_m / blu, dmax, 1e-3) << q.x0;  // the brute force samples every 1e-3 BLU or so
  }
}

// A 45-degree line: through the nodes, each step pair cuts off a triangle of 1/2 BLU^2; shifted by a quarter BLU
// along x, each cell holds two triangles, of 1/32 and 9/32 BLU^2 (docs/compare.md works it out).
TEST(CartesianError, FortyFiveDegreeLines) {
  const double blu = 0.05e-3;
  const int n = 40;
  {
    auto line = make_line({0, 0}, {n * blu, n * blu});
    XYRun r = exact_run(*line, blu);
    EXPECT_NEAR(r.m.area.area_m2, 0.5 * n * blu * blu, 1e-12 * n * blu * blu);
    EXPECT_NEAR(r.general.area_m2, 0.5 * n * blu * blu, 1e-12 * n * blu * blu);
    // the staircase's outer corners are 1/sqrt(2) BLU from the line
    EXPECT_NEAR(r.m.deviation_max_m, blu / std::sqrt(2.0), 1e-9 * blu);
  }
  {
    auto line = make_line({0.25 * blu, 0}, {(n + 0.25) * blu, n * blu});
    XYRun r = exact_run(*line, blu);
    EXPECT_NEAR(r.m.area.area_m2, 5.0 * n / 16.0 * blu * blu, 1e-12 * n * blu * blu);
    EXPECT_NEAR(r.general.area_m2, 5.0 * n / 16.0 * blu * blu, 1e-12 * n * blu * blu);
    // the corner (k + 1, k) is 0.75 / sqrt(2) BLU from the line y = x - 1/4
    EXPECT_NEAR(r.m.deviation_max_m, 0.75 / std::sqrt(2.0) * blu, 1e-9 * blu);
  }
}

// Polygons stepped at exact times and by the DDA: the strip meter against CGAL's exact arrangement of the very
// same segments.
TEST(CartesianError, PolygonsAgainstCgal) {
  const double blu = 0.2e-3;
  std::vector<std::vector<Vec2>> polys;
  {
    std::vector<Vec2> v;  // a star with concave corners and edges at many angles
    for (int i = 0; i < 14; ++i) {
      const double a = 2 * kPi * i / 14 + 0.1, r = (i % 2 ? 9.3 : 21.7) * blu;
      v.push_back({r * std::cos(a) + 3.3 * blu, r * std::sin(a) - 1.7 * blu});
    }
    polys.push_back(v);
  }
  polys.push_back({{0.4 * blu, 0.2 * blu}, {30.6 * blu, 0.2 * blu}, {30.6 * blu, 20.1 * blu}, {15.0 * blu, 5.3 * blu},
                   {0.4 * blu, 20.1 * blu}});  // a notch down to near the bottom edge
  for (const auto& v : polys) {
    auto path = polygon(v);
    std::vector<Vec2> closed_poly = v;
    closed_poly.push_back(v.front());
    XYRun r = exact_run(*path, blu);
    const double ref = area_error_cgal_cartesian(closed_poly, nodes_of(r.res.start, r.steps), blu);
    EXPECT_GT(ref, 0.0);
    EXPECT_NEAR(r.m.area.area_m2, ref, 1e-10 * ref) << r.m.area.sectors << " strips, " << r.m.area.general_sectors
                                                      << " general";
    EXPECT_NEAR(r.general.area_m2, ref, 1e-10 * ref);

    // the DDA's staircase of the same polygon (its lines rounded to nodes)
    std::vector<PathSegment> segs;
    for (size_t i = 0; i < v.size(); ++i) segs.push_back({PathSegment::Kind::line, v[i], v[(i + 1) % v.size()], {}, 0});
    DdaProgram prog = make_dda_program(segs, true, blu, 0.002, DdaOptions{});
    RecordingSink rec;
    CartesianResult dr = run_dda(prog, &rec);
    CartesianTrack track = CartesianTrack::build(*path);
    CartesianErrorMetrics dm = measure(*path, track, blu, rec.steps, dr.start);
    const double dref = area_error_cgal_cartesian(closed_poly, nodes_of(dr.start, rec.steps), blu);
    EXPECT_NEAR(dm.area.area_m2, dref, 1e-10 * dref);
  }
}

// A circle of radius R about a node, open at its seam or not: the area against CGAL on inscribed polygons
// (Richardson-extrapolated), the deviation against the closed form: on an axis-aligned unit segment the distance
// ||p| - R| is largest at an end (|p| convex) or, inside the circle, at the foot of the perpendicular from the
// centre.
TEST(CartesianError, CircleAreaAndDeviation) {
  const double blu = 0.5e-3, R = 23.37 * blu;
  const Vec2 c{4.21 * blu, -2.6 * blu};
  auto circle = make_circle(c, R);
  for (bool dda : {false, true}) {
    std::vector<test::Recorded> steps;
    int64_t start[2];
    CartesianTrack track = CartesianTrack::build(*circle);
    if (!dda) {
      auto prof = make_constant_speed(0.01, track.length());
      RecordingSink rec;
      CartesianResult res = step_exact(track, blu, *prof, &rec);
      steps = rec.steps;
      start[0] = res.start[0], start[1] = res.start[1];
    } else {
      std::vector<PathSegment> quarters;
      Vec2 p = c + Vec2{R, 0};
      for (int q = 0; q < 4; ++q) {
        quarters.push_back(make_arc_segment(p, c, 0.5 * kPi));
        p = quarters.back().to;
      }
      quarters.back().to = c + Vec2{R, 0};
      DdaProgram prog = make_dda_program(quarters, true, blu, 0.01, DdaOptions{});
      RecordingSink rec;
      CartesianResult res = run_dda(prog, &rec);
      steps = rec.steps;
      start[0] = res.start[0], start[1] = res.start[1];
    }
    CartesianErrorMetrics m = measure(*circle, track, blu, steps, start);

    // deviation by closed form
    const auto nodes = nodes_of(start, steps);
    auto d_at = [&](Vec2 p) { return std::abs(norm(p - c) - R); };
    double dmax = 0;
    for (size_t k = 0; k + 1 < nodes.size(); ++k) {
      const Vec2 a{nodes[k].i * blu, nodes[k].j * blu}, b{nodes[k + 1].i * blu, nodes[k + 1].j * blu};
      dmax = std::max({dmax, d_at(a), d_at(b)});
      const Vec2 d = b - a;
      const double t = dot(c - a, d) / dot(d, d);
      if (t > 0 && t < 1) dmax = std::max(dmax, d_at(a + t * d));
    }
    EXPECT_NEAR(m.deviation_max_m, dmax, 1e-9 * blu) << (dda ? "dda" : "exact");

    // area against CGAL on inscribed polygons of M and 2M sides
    auto cgal = [&](int M) {
      std::vector<Vec2> v;
      for (int i = 0; i <= M; ++i) v.push_back(c + R * Vec2{std::cos(2 * kPi * (i % M) / M), std::sin(2 * kPi * (i % M) / M)});
      return area_error_cgal_cartesian(v, nodes, blu);
    };
    const double a1 = cgal(1200), a2 = cgal(2400), extrapolated = (4 * a2 - a1) / 3;
    EXPECT_NEAR(m.area.area_m2, extrapolated, 1e-6 * extrapolated) << (dda ? "dda" : "exact");
  }
}

// A staircase that was not made from the path is refused with a clear message.
TEST(CartesianError, RefusesAStaircaseOfAnotherPath) {
  const double blu = 0.1e-3;
  auto line = make_line({0, 0}, {20 * blu, 0});
  CartesianTrack track = CartesianTrack::build(*line);
  CartesianErrorMeters em;
  em.reset(*line, track, blu);
  for (int k = 0; k < 20; ++k) em.record(kAxisX, +1);
  EXPECT_NO_THROW(em.finish(0, 0));
  em.reset(*line, track, blu);
  for (int k = 0; k < 20; ++k) em.record(kAxisX, +1);
  try {
    em.finish(0, 7);
    FAIL() << "accepted a staircase 7 BLU away";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does not follow this path"), std::string::npos) << e.what();
  }
  em.reset(*line, track, blu);
  for (int k = 0; k < 40; ++k) em.record(kAxisX, +1);
  for (int k = 0; k < 20; ++k) em.record(kAxisX, -1);
  try {
    em.finish(0, 0);
    FAIL() << "accepted a staircase that runs 20 BLU past the path";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x step 24"), std::string::npos) << e.what();
  }
}

// The staircase of a recorded Cartesian run, piece by piece, into a deviation meter (window 3 BLU).
void feed_staircase(DeviationMeter& dm, const CartesianResult& res, const RecordingSink& rec, double blu) {
  int64_t node[2] = {res.start[0], res.start[1]};
  dm.start(cartesian_position(node, blu), 3 * blu);
  for (const auto& s : rec.steps) {
    StairPiece piece;
    piece.a = cartesian_position(node, blu);
    node[s.axis] += s.dir;
    piece.b = cartesian_position(node, blu);
    dm.piece(piece, 3 * blu);
  }
}

// The deviation's foot-point tracking (Newton from the previous foot) gives the same largest distance as the
// window search at every point, on a smooth closed path with a dimple (a limacon) and on an open one with ends.
TEST(CartesianError, DeviationTrackingAgreesWithTheWindowSearch) {
  const double blu = 0.05e-3;
  for (auto path : {make_limacon(0.0308, 0.0362), make_witch(0.02, -0.03, 0.03)}) {
    CartesianTrack track = CartesianTrack::build(*path);
    auto prof = make_constant_speed(0.02, track.length());
    RecordingSink rec;
    const CartesianResult res = step_exact(track, blu, *prof, &rec);
    double dev[2];
    for (int full = 0; full < 2; ++full) {
      DeviationMeter dm(*path);
      dm.set_full_search(full == 1);
      feed_staircase(dm, res, rec, blu);
      dev[full] = dm.max();
    }
    EXPECT_GT(dev[0], 0.5 * blu);
    EXPECT_NEAR(dev[0], dev[1], 1e-12 * blu) << path->name();
  }
}

// The deviation's local model (a cubic Taylor polynomial of the path about an anchor, taken only where it agrees
// with the path to rounding) gives the same largest distance and the same place as tracking on the path itself,
// where the grid is fine enough for it (here 200 times the BLU below, and it is used there); on a grid as coarse
// as the thesis's it is never taken.
TEST(CartesianError, DeviationLocalModelAgreesWithThePath) {
  for (auto path : {make_limacon(0.0308, 0.0362), make_witch(0.02, -0.03, 0.03)}) {
    CartesianTrack track = CartesianTrack::build(*path);
    for (const double blu : {0.0254e-3, 0.25e-6}) {
      auto prof = make_constant_speed(0.02, track.length());
      RecordingSink rec;
      const CartesianResult res = step_exact(track, blu, *prof, &rec);
      double dev[2];
      Vec2 at[2];
      uint64_t anchors = 0;
      for (int model = 0; model < 2; ++model) {
        DeviationMeter dm(*path);
        dm.set_model(model == 1);
        feed_staircase(dm, res, rec, blu);
        dev[model] = dm.max();
        at[model] = dm.at();
        if (model == 1) anchors = dm.anchors();
      }
      if (blu > 1e-5) {
        EXPECT_EQ(anchors, 0u) << path->name();
        EXPECT_EQ(dev[0], dev[1]) << path->name();
      } else {
        EXPECT_GT(anchors, 10u) << path->name();
        EXPECT_LT(anchors, rec.steps.size() / 10) << path->name();  // a stretch serves tens of steps here
      }
      EXPECT_GT(dev[0], 0.5 * blu);
      // the distance of one point differs by the rounding of the path's coordinates, about 1e-17 m
      EXPECT_NEAR(dev[0], dev[1], 1e-9 * dev[0]) << path->name() << " blu " << blu;
      // at the same point, or at its mirror image: both contours are symmetric (the limacon about the x axis, the
      // witch about the y axis), and the two largest distances are equal but for rounding
      const bool same = at[0].x == at[1].x && at[0].y == at[1].y;
      const bool mirror = std::abs(std::abs(at[0].x) - std::abs(at[1].x)) < 1e-3 * blu &&
                          std::abs(std::abs(at[0].y) - std::abs(at[1].y)) < 1e-3 * blu;
      EXPECT_TRUE(same || mirror) << path->name() << " blu " << blu << ": (" << at[0].x << ", " << at[0].y
                                  << ") and (" << at[1].x << ", " << at[1].y << ")";
    }
  }
}

}  // namespace tu_metrics_test_cartesian_error
