// The area error against an independent exact computation with CGAL (metrics/area_check.hpp): an arrangement of
// the contour, the connectors and the staircase's radial segments and arcs about the pole, in exact arithmetic.
// For polygonal contours both sides see the very same curve, so they must agree to rounding; for a smooth contour
// CGAL sees fine polygons, and Richardson extrapolation in the number of sides removes the polygon's error.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/area_helpers.hpp"
#include "cam/curves.hpp"
#include "cam/path.hpp"
#include "metrics/area_check.hpp"

namespace tu_metrics_test_area_cgal {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {

constexpr double kPi = std::numbers::pi;

std::vector<StairNode> stair(const AreaRun& r) {
  std::vector<StairNode> v;
  for (const Node& n : nodes_of(r)) v.push_back({n.n, n.m});
  return v;
}

// A polygonal contour (vertices in the contour frame), placed; returns the path and its vertices in the machine
// frame.
struct Poly {
  ToolPathPtr path;
  std::vector<Vec2> machine;
};
Poly polygon(const std::vector<Vec2>& v, bool closed, Placement pl) {
  std::vector<PathSegment> segs;
  const size_t n = closed ? v.size() : v.size() - 1;
  for (size_t i = 0; i < n; ++i) segs.push_back({PathSegment::Kind::line, v[i], v[(i + 1) % v.size()], {}, 0});
  Poly p;
  p.path = make_tool_path(make_path(segs, closed), pl, ToolSpec{}, TravelSpec{});
  for (const Vec2& x : v) p.machine.push_back(x - pl.pole());
  if (closed) p.machine.push_back(p.machine.front());
  return p;
}

void check_polygon(const char* name, const std::vector<Vec2>& v, bool closed, Placement pl, const Grid& g) {
  Poly p = polygon(v, closed, pl);
  for (StepRule rule : {StepRule::nearest, StepRule::thesis}) {
    AreaRun r = area_run(*p.path, g, rule);
    const double ref = area_error_cgal(p.machine, stair(r), g.dr, g.dtheta, g.steps_per_rev);
    EXPECT_GT(ref, 0.0);
    EXPECT_NEAR(r.area.area_m2, ref, 1e-10 * ref) << name << ", rule " << to_string(rule) << ": " << r.area.sectors
                                                  << " sectors, " << r.area.general_sectors << " general";
  }
}

}  // namespace

// A polygonal circle with the pole outside: every ray meets it twice, and near the two tangent rays the contour
// turns back within a sector (not star-shaped about the pole).
TEST(AreaCgal, PolygonPoleOutside) {
  std::vector<Vec2> v;
  for (int i = 0; i < 90; ++i) v.push_back({0.02 * std::cos(2 * kPi * i / 90), 0.02 * std::sin(2 * kPi * i / 90)});
  check_polygon("circle polygon", v, true, Placement{0.06, 1.1 * kPi}, coarse_grid(0.5e-3, 1000));
}

// An open polyline on a witch of Agnesi (star-shaped about the pole), and a closed one around the pole.
TEST(AreaCgal, PolygonOpenAndAroundThePole) {
  std::vector<Vec2> w;
  const double a = 0.05;
  for (int i = 0; i <= 60; ++i) {
    const double x = -0.06 + 0.12 * i / 60;
    w.push_back({x, 8 * a * a * a / (x * x + 4 * a * a)});
  }
  check_polygon("witch polyline", w, false, Placement{0.03, 1.3}, coarse_grid(0.4e-3, 1200));
  std::vector<Vec2> l;
  for (int i = 0; i < 80; ++i) {
    const double t = 2 * kPi * i / 80, r = 0.03 + 0.02 * std::cos(t);
    l.push_back({r * std::cos(t), r * std::sin(t)});
  }
  check_polygon("limacon polygon", l, true, Placement{0.006, 0.4}, coarse_grid(0.4e-3, 800));
}

// An open hairpin that passes close to the pole and doubles back in angle, with stretches nearly radial.
TEST(AreaCgal, PolygonHairpinNearThePole) {
  std::vector<Vec2> v;
  for (int i = 0; i <= 70; ++i) {
    const double t = -1.4 + 2.8 * i / 70;
    v.push_back({0.03 * std::cos(t) - 0.02, 0.05 * std::sin(t) * std::cos(t)});
  }
  check_polygon("hairpin", v, false, Placement{0.012, 0.2}, coarse_grid(0.3e-3, 900));
}

// A smooth circle with the pole outside: CGAL on inscribed polygons of M and 2M sides, extrapolated.
TEST(AreaCgal, SmoothCircleRichardson) {
  const Grid g = coarse_grid(0.5e-3, 1000);
  const Placement pl{0.06, 0.7};
  const double R = 0.02;
  auto path = make_tool_path(make_circle({0, 0}, R), pl, ToolSpec{}, TravelSpec{});
  AreaRun r = area_run(*path, g, StepRule::nearest);
  auto cgal = [&](int M) {
    std::vector<Vec2> v;
    for (int i = 0; i <= M; ++i) {
      const double t = 2 * kPi * (i % M) / M;
      v.push_back(Vec2{R * std::cos(t), R * std::sin(t)} - pl.pole());
    }
    return area_error_cgal(v, stair(r), g.dr, g.dtheta, g.steps_per_rev);
  };
  const double a1 = cgal(1500), a2 = cgal(3000), extrapolated = (4 * a2 - a1) / 3;
  EXPECT_NEAR(r.area.area_m2, extrapolated, 1e-6 * extrapolated) << "M: " << a1 << ", 2M: " << a2;
  EXPECT_GT(std::abs(a1 - r.area.area_m2), std::abs(extrapolated - r.area.area_m2));
}

}  // namespace tu_metrics_test_area_cgal
