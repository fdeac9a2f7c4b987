// Pole placement: Hooke and Jeeves, the constraints, the F1 path of the thesis, the NLopt path on the exact area,
// the maps, and determinism whatever the number of threads.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/area_helpers.hpp"
#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "optimize/hooke_jeeves.hpp"
#include "optimize/placement.hpp"

namespace tu_optimize_test_placement {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {

constexpr double kPi = std::numbers::pi;

CurvePtr at_zero(CurvePtr c) { return make_tool_path(std::move(c), Placement{}, ToolSpec{}, TravelSpec{}); }

// A small, cheap problem: a circle of 2 cm on a coarse grid with a work area.
PoleProblem small_problem(PoleObjective obj, bool outside = false) {
  Grid g = coarse_grid(0.2e-3, 2000);
  g.r_min = 0.01;
  g.r_max = 0.08;
  g.theta_min = 0.0;
  g.theta_max = 2.8;
  return make_pole_problem(at_zero(make_circle({0, 0}, 0.02)), g, StepRule::nearest, obj, 40, outside);
}

// The area objective's search from one start beside the circle, with `evaluations` and `threads`.
const Placement kAreaStart{0.05, 1.5 * kPi + 0.2};
PlacementOptions area_search(int evaluations, int threads) {
  PlacementOptions o;
  o.max_evaluations = evaluations;
  o.threads = threads;
  return o;
}

}  // namespace

TEST(HookeJeeves, FindsTheMinimumOfAQuadraticAndRespectsInfeasibility) {
  auto q = [](const std::vector<double>& x) {
    return (x[0] - 1.0) * (x[0] - 1.0) + 3.0 * (x[1] - 2.0) * (x[1] - 2.0) + 0.5 * x[0] * x[1];
  };
  HookeJeevesOptions o;
  o.step = {0.5, 0.5};
  o.min_step = {1e-9, 1e-9};
  o.max_evaluations = 5000;
  // unconstrained: the gradient vanishes at y = 11.5 / 5.875, x = 1 - y / 4
  const HookeJeevesResult r = hooke_jeeves(q, {-3.0, -3.0}, o);
  EXPECT_NEAR(r.x[1], 11.5 / 5.875, 1e-6);
  EXPECT_NEAR(r.x[0], 1.0 - 0.25 * 11.5 / 5.875, 1e-6);
  EXPECT_GE(r.bases.size(), 3u);
  // a wall x >= 0.8 (infeasible points are +infinity): the minimum slides along it to y = 2 - 0.4 / 6
  auto f = [&](const std::vector<double>& x) { return x[0] < 0.8 ? std::numeric_limits<double>::infinity() : q(x); };
  const HookeJeevesResult w = hooke_jeeves(f, {3.0, -3.0}, o);
  EXPECT_NEAR(w.x[0], 0.8, 1e-6);
  EXPECT_NEAR(w.x[1], 2.0 - 0.4 / 6.0, 1e-6);
}

TEST(ContourInside, SquareInsideOutsideAndDistance) {
  ContourInside sq({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  EXPECT_TRUE(sq.inside({0.5, 0.5}));
  EXPECT_FALSE(sq.inside({1.5, 0.5}));
  EXPECT_TRUE(sq.inside({1.0, 0.5}));  // on the boundary counts as inside
  EXPECT_NEAR(sq.boundary_distance({0.5, 0.2}), 0.2, 1e-15);
  EXPECT_NEAR(sq.boundary_distance({2.0, 2.0}), std::sqrt(2.0), 1e-15);
}

// The margin's sign agrees with the digitizer's own work-area check.
TEST(Placement, MarginAgreesWithTheDigitizer) {
  PoleProblem p = small_problem(PoleObjective::area);
  PoleEvaluator ev(p);
  int feasible = 0, infeasible = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec2 pole{-0.1 + 0.2 * ((i * 37) % 400) / 400.0, -0.1 + 0.2 * ((i * 91) % 400) / 400.0};
    const PoleValue v = ev.margin(pole);
    if (!v.computed) continue;
    PolarTrack tr = PolarTrack::build(*translated(p.path0, -pole));
    bool ok = true;
    try {
      place_on_grid(tr, p.grid);
    } catch (const InputError&) {
      ok = false;
    }
    if (std::abs(v.margin) < 1e-9) continue;
    EXPECT_EQ(ok, v.margin > 0) << pole.x << ", " << pole.y << " margin " << v.margin;
    (ok ? feasible : infeasible)++;
  }
  EXPECT_GT(feasible, 20);
  EXPECT_GT(infeasible, 20);
}

// The thesis's path: F1 and Hooke-Jeeves from the job's placement (C = 1.27 cm, beta = 0) at the thesis's
// resolution. The listing HOKJEV replicated finds its minimum 0.34 in from O1 towards the small loop; Table 4.1
// gives C = 0.86 cm (docs/table-4-1.md on beta).
TEST(Placement, LimaconF1HookeJeeves) {
  const Grid g = coarse_grid(0.0254e-3, 16000);
  PoleProblem p = make_pole_problem(at_zero(make_limacon(0.0508, 0.0762)), g, StepRule::nearest, PoleObjective::f1,
                                    100, false);
  PlacementOptions o;
  o.objective = PoleObjective::f1;
  o.method = PoleMethod::hooke_jeeves;
  const PlacementResult r = optimize_placement(p, Placement{0.0127, 0.0}, o);
  EXPECT_NEAR(r.placement.C, 0.0086, 0.0005);
  EXPECT_NEAR(r.placement.beta, kPi, 0.05);
  EXPECT_LT(r.at.value, r.start.value);
  EXPECT_GT(r.path.size(), 2u);
}

// NLopt on the exact area: feasible, no worse than the start or than any point of an independent lattice scan by
// more than the fine-scale fluctuation, and identical with one or two threads.
TEST(Placement, NloptAreaIsDeterministicAndGood) {
  PoleProblem p = small_problem(PoleObjective::area);
  PlacementOptions o = area_search(240, 1);
  const Placement start = kAreaStart;
  const PlacementResult a = optimize_placement(p, start, o);
  o.threads = 2;
  const PlacementResult b = optimize_placement(p, start, o);
  EXPECT_EQ(a.pole.x, b.pole.x);
  EXPECT_EQ(a.pole.y, b.pole.y);
  EXPECT_EQ(a.at.area_m2, b.at.area_m2);
  EXPECT_EQ(a.evaluations, b.evaluations);
  ASSERT_TRUE(a.at.feasible());
  ASSERT_TRUE(a.start.feasible());
  EXPECT_LE(a.at.area_m2, a.start.area_m2);
  const ObjectiveMap m = objective_map(p, feasible_box(p, search_box(p), 21, 2), 13, 13, 2);
  double best = INFINITY;
  for (double v : m.value)
    if (std::isfinite(v)) best = std::min(best, v);
  ASSERT_TRUE(std::isfinite(best));
  EXPECT_LE(a.at.area_m2, 1.01 * best);
}

TEST(Placement, HoldsKeepCOrBeta) {
  PoleProblem p = small_problem(PoleObjective::area);
  PlacementOptions o = area_search(60, 2);
  const Placement start = kAreaStart;
  o.hold = PoleHold::C;
  const PlacementResult c = optimize_placement(p, start, o);
  EXPECT_DOUBLE_EQ(c.placement.C, start.C);
  EXPECT_NEAR(norm(c.pole), start.C, 1e-15);
  o.hold = PoleHold::beta;
  const PlacementResult b = optimize_placement(p, start, o);
  EXPECT_DOUBLE_EQ(b.placement.beta, start.beta);
  EXPECT_NEAR(std::remainder(std::atan2(b.pole.y, b.pole.x) - start.beta, 2 * kPi), 0.0, 1e-12);
}

// A closed contour whose best pole lies inside it when allowed (the limacon, exact area): with the constraint, the
// result is outside.
TEST(Placement, PoleOutsideAClosedContour) {
  Grid g = coarse_grid(0.2e-3, 2000);
  g.r_max = 0.3302;
  auto make = [&](bool outside) {
    return make_pole_problem(at_zero(make_limacon(0.0508, 0.0762)), g, StepRule::nearest, PoleObjective::area, 40,
                             outside);
  };
  PoleProblem free = make(false), out = make(true);
  PlacementOptions o;
  o.max_evaluations = 160;
  const PlacementResult a = optimize_placement(free, Placement{0.0127, 0.0}, o);
  const PlacementResult b = optimize_placement(out, Placement{0.0127, 0.0}, o);
  ASSERT_TRUE(out.keep_outside);
  EXPECT_TRUE(out.keep_outside->inside(a.pole)) << "the unconstrained optimum should lie inside the limacon";
  EXPECT_FALSE(out.keep_outside->inside(b.pole));
  EXPECT_GE(b.at.margin, 0.0);
  EXPECT_FALSE(b.start.feasible());  // the job's own pole is inside
  // an open contour cannot keep the pole outside
  EXPECT_THROW(make_pole_problem(at_zero(make_line({0.01, 0}, {0.02, 0.01})), g, StepRule::nearest,
                                 PoleObjective::area, 10, true),
               InputError);
}

TEST(Placement, MapIsTheSameOnOneOrTwoThreads) {
  PoleProblem p = small_problem(PoleObjective::area);
  const SearchBox box = feasible_box(p, search_box(p), 21, 2);
  const ObjectiveMap a = objective_map(p, box, 9, 7, 1), b = objective_map(p, box, 9, 7, 2);
  ASSERT_EQ(a.value.size(), 63u);
  int feasible = 0;
  for (size_t i = 0; i < a.value.size(); ++i) {
    EXPECT_TRUE((std::isnan(a.value[i]) && std::isnan(b.value[i])) || a.value[i] == b.value[i]) << i;
    feasible += std::isfinite(a.value[i]);
  }
  EXPECT_GT(feasible, 5);
}

}  // namespace tu_optimize_test_placement
