// The exact area error against closed forms, and its fast path against its general sweep.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/area_helpers.hpp"
#include "cam/curves.hpp"
#include "cam/error.hpp"

namespace tu_metrics_test_area_error {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {

constexpr double kPi = std::numbers::pi;

ToolPathPtr placed(CurvePtr c, double C, double beta) {
  return make_tool_path(std::move(c), Placement{C, beta}, ToolSpec{}, TravelSpec{});
}

double shoelace(const std::vector<Vec2>& p) {
  double a = 0;
  for (size_t i = 0; i < p.size(); ++i) a += cross(p[i], p[(i + 1) % p.size()]);
  return 0.5 * a;
}

}  // namespace

// A circle about the machine pole: the staircase is the circle of the node radius, so the area error is the
// annulus between the two circles, pi |R^2 - (n dR)^2|, for both rules.
TEST(AreaError, CircleAboutThePoleIsAnAnnulus) {
  const Grid g = coarse_grid(1e-3, 720);
  for (double frac : {0.3, 0.7}) {
    const double R = (50.0 + frac) * g.dr;
    auto path = placed(make_circle({0, 0}, R), 0.0, 0.0);
    for (StepRule rule : {StepRule::nearest, StepRule::thesis}) {
      AreaRun r = area_run(*path, g, rule);
      const double n = rule == StepRule::nearest ? std::nearbyint(R / g.dr) : std::floor(R / g.dr);
      const double expect = kPi * std::abs(R * R - n * g.dr * n * g.dr);
      EXPECT_EQ(r.area.rise_steps, 0u);
      EXPECT_EQ(r.area.run_steps, 720u);
      EXPECT_NEAR(r.area.area_m2, expect, 1e-12 * expect) << to_string(rule) << " frac " << frac;
    }
  }
}

// A radial line between two grid rays: the staircase runs down the nearest ray, and the cycle closed by the two
// straight connectors is a quadrilateral whose area the shoelace formula gives.
TEST(AreaError, RadialLineIsAQuadrilateral) {
  const Grid g = coarse_grid(1e-3, 360);
  const double phi = (12.0 + 0.3) * g.dtheta, r1 = 40.37e-3, r2 = 71.81e-3;
  auto path = placed(make_line({r1 * std::cos(phi), r1 * std::sin(phi)}, {r2 * std::cos(phi), r2 * std::sin(phi)}),
                     0.0, 0.0);
  for (StepRule rule : {StepRule::nearest, StepRule::thesis}) {
    AreaRun r = area_run(*path, g, rule);
    auto nodes = nodes_of(r);
    auto pt = [&](const Node& n) {
      const double rho = n.n * g.dr, a = n.m * g.dtheta;
      return Vec2{rho * std::cos(a), rho * std::sin(a)};
    };
    std::vector<Vec2> quad{{r1 * std::cos(phi), r1 * std::sin(phi)}, {r2 * std::cos(phi), r2 * std::sin(phi)},
                           pt(nodes.back()), pt(nodes.front())};
    const double expect = std::abs(shoelace(quad));
    EXPECT_EQ(r.area.run_steps, 0u);
    EXPECT_NEAR(r.area.area_m2, expect, 1e-12 * expect) << to_string(rule);
  }
}

// The fast path (one or several clear passes per sector) and the general sweep give the same area. The fast path
// takes the sectors' edges from fits of the track as series of the angle where a segment of the walk spans 48
// edges or more (all these cases), the general sweep integrates the track's own series between them. Both carry
// the rounding of the swept-area series (values of the order of a piece's swept area, differenced sector by
// sector): on the grid ten times finer than the others the two agree to 1e-10, not 1e-11.
TEST(AreaError, FastPathAgreesWithGeneralSweep) {
  struct Case {
    const char* name;
    ToolPathPtr path;
    Grid grid;
    double rel = 1e-11;
  };
  std::vector<Case> cases = {
      {"limacon, pole inside", placed(make_limacon(0.0508, 0.0762), 0.0127, 0.0), coarse_grid(0.1e-3, 4000)},
      {"witch", placed(make_witch(0.2159, -0.2032, 0.2032), 0.1546, 1.236), coarse_grid(0.1e-3, 4000)},
      {"circle, pole outside", placed(make_circle({0, 0}, 0.0508), 0.2032, 1.5 * kPi), coarse_grid(0.1e-3, 4000)},
      {"serpentine near the pole", placed(make_serpentine(0.0127, 0.0762, -0.0762, 0.0762), 0.0537, 4.247),
       coarse_grid(0.1e-3, 4000)},
      {"limacon, a grid ten times finer", placed(make_limacon(0.0508, 0.0762), 0.0127, 0.0),
       coarse_grid(0.01e-3, 40000), 1e-10},
  };
  for (const auto& c : cases) {
    for (StepRule rule : {StepRule::nearest, StepRule::thesis}) {
      AreaRun fast = area_run(*c.path, c.grid, rule, false);
      AreaRun gen = area_run(*c.path, c.grid, rule, true);
      EXPECT_GT(fast.area.area_m2, 0.0);
      EXPECT_NEAR(fast.area.area_m2, gen.area.area_m2, c.rel * gen.area.area_m2) << c.name << " " << to_string(rule);
      EXPECT_LT(fast.area.general_sectors * 10, fast.area.sectors) << c.name;
      EXPECT_EQ(gen.area.general_sectors, gen.area.sectors);
    }
  }
}

}  // namespace tu_metrics_test_area_error
