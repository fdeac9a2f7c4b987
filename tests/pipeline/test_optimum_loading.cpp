// Pole placement for balanced axis torque and the capacity scaling (optimize/placement, optimize/capacity;
// docs/optimum-loading.md), through the job glue that `polarcam optimize` and `polarcam capacity` use:
//  - the balanced optimum against an independent dense search of the same objective (a lattice over the search box
//    and a finer lattice around its best feasible point): nothing found more than 1 % better;
//  - the largest speed and load fed back into the analysis of `analyze` give the worst torque ratio 1 / SF;
//  - the Pareto front's constrained points against a dense search of the least area within their worst ratio.
// All eight jobs of examples/ch6 (about 50 s of CPU in a Release build); under the sanitizers the inertial circle
// only, unless POLARCAM_LONG_TESTS=1 is in the environment.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "job/job.hpp"
#include "pipeline/job_analysis.hpp"
#include "pipeline/job_capacity.hpp"
#include "pipeline/job_placement.hpp"
#include "optimize/pareto.hpp"
#include "optimize/placement.hpp"
#include "tests/dense_pole_search.hpp"

namespace tu_pipeline_test_optimum_loading {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

std::string example(const std::string& name) { return std::string(POLARCAM_SOURCE_DIR) + "/examples/ch6/" + name + ".toml"; }

// The balanced objective's value at a pole (feasible points only), +inf elsewhere.
double balanced_at(const PoleValue& v) {
  if (!v.feasible() || !v.torque_computed || !v.torque.computed) return std::numeric_limits<double>::infinity();
  return v.torque.balanced;
}

}  // namespace

// the fixture outside the anonymous namespace: the test class derived from it is in the file's namespace
class BalancedOptimum : public ::testing::TestWithParam<const char*> {};

TEST_P(BalancedOptimum, NoDenseSearchFindsMoreThanOnePercentBetter) {
  const std::string name = GetParam();
#ifdef POLARCAM_SANITIZED
  if (!test::long_tests() && name != "circle_inertial") GTEST_SKIP() << "checked in the normal build";
#endif
  const Job job = load_job(example(name));
  PlacementOptions o = job.optimize;  // as `polarcam optimize` starts (the job's [optimize] section)
  o.objective = PoleObjective::balanced;
  o.threads = 2;
  const PoleProblem p = job_pole_problem(job, o, true);
  const PlacementResult r = optimize_placement(p, job.placement, o);
  ASSERT_TRUE(r.at.feasible());
  const double found = balanced_at(r.at);
  ASSERT_TRUE(std::isfinite(found));
  // the independent search: 33 x 33 over the whole search box, then 21 x 21 over +-1 cell around the best (under
  // the sanitizers, whose run checks the memory and the undefined behaviour of the same calls, 17 x 17 and 11 x 11)
  const SearchBox box = search_box(p);
#ifdef POLARCAM_SANITIZED
  const int n = 17, n_fine = 11;
#else
  const int n = 33, n_fine = 21;
#endif
  const test::DenseBest coarse = test::dense_search(p, box, n, balanced_at);
  ASSERT_TRUE(std::isfinite(coarse.value));
  const double hx = (box.x1 - box.x0) / (n - 1), hy = (box.y1 - box.y0) / (n - 1);
  const test::DenseBest fine = test::dense_search(p, {coarse.pole.x - hx, coarse.pole.x + hx, coarse.pole.y - hy, coarse.pole.y + hy}, n_fine, balanced_at);
  const double best = std::min(coarse.value, fine.value);
  EXPECT_GE(best, 0.99 * found) << name << ": optimize " << found << " at (" << r.pole.x << ", " << r.pole.y
                                << "), dense " << best;
  // and the optimum is no worse than the job's own placement when that is feasible
  if (r.start.feasible() && std::isfinite(balanced_at(r.start))) {
    EXPECT_LE(found, balanced_at(r.start) * (1 + 1e-12));
  }
}

INSTANTIATE_TEST_SUITE_P(Ch6, BalancedOptimum,
                         ::testing::Values("circle_inertial", "witch_grinding", "circle_grinding", "witch_inertial",
                                           "limacon_inertial", "limacon_grinding", "serpentine_inertial",
                                           "serpentine_grinding"));

// a fixture outside the anonymous namespace: the test class derived from it is in the file's namespace
class CapacityFeedback : public ::testing::TestWithParam<const char*> {};

TEST_P(CapacityFeedback, LargestSpeedAndLoadGiveTheLimitInTheAnalysis) {
  const Job job = load_job(example(GetParam()));
  const PreparedDynamics prep = prepare_dynamics(job);
  const JobCapacity c = job_capacity(job, prep, std::nullopt, 0);
  ASSERT_TRUE(c.speed.has_value());
  ASSERT_TRUE(c.speed_cap.factor.has_value());
  ASSERT_FALSE(c.speed_cap.capped);
  const double limit = 1.0 / job.safety_factor;
  EXPECT_DOUBLE_EQ(c.limit, limit);
  AnalysisOptions a;
  a.keep_series = false;
  auto worst = [](const CaseResult& r) { return std::max(r.analysis.radial.ratio.value, r.analysis.angular.ratio.value); };
  // the speed, at the job's load
  const double v = *c.speed * *c.speed_cap.factor;
  const CaseResult at_v = analyze_case(job, prep, DynamicsCase{v, job.load}, a, false);
  EXPECT_NEAR(worst(at_v), limit, 1e-3);
  // a little faster fails, a little slower passes
  EXPECT_GT(worst(analyze_case(job, prep, DynamicsCase{v * 1.01, job.load}, a, false)), limit);
  EXPECT_LT(worst(analyze_case(job, prep, DynamicsCase{v * 0.99, job.load}, a, false)), limit);
  // the load, at the job's speed
  ASSERT_TRUE(c.load_cap.value.has_value());
  ASSERT_FALSE(c.load_cap.capped);
  const LoadSpec l = scaled_load(job.load, c.measure, *c.load_cap.value);
  const CaseResult at_l = analyze_case(job, prep, DynamicsCase{std::nullopt, l}, a, false);
  EXPECT_NEAR(worst(at_l), limit, 1e-3);
  const LoadSpec more = scaled_load(job.load, c.measure, *c.load_cap.value * 1.02);
  EXPECT_GT(worst(analyze_case(job, prep, DynamicsCase{std::nullopt, more}, a, false)), limit);
}

INSTANTIATE_TEST_SUITE_P(Ch6, CapacityFeedback, ::testing::Values("circle_inertial", "witch_grinding"));

// The Pareto front of area error against the worst torque ratio (optimize/pareto): at the front's points found by
// its constrained searches (the levels), an independent dense search of the least area error among the poles
// whose worst ratio is no higher finds nothing more than 1 % better (a 33 x 33 grid over the search box, then
// 21 x 21 over the cells around its best, or around the level's pole where no grid pole is within its limit). The witch with the grinding load (the
// operator's report's job); under the sanitizers only with POLARCAM_LONG_TESTS=1.
TEST(ParetoFront, NoDenseSearchFindsALevelMoreThanOnePercentBetter) {
#ifdef POLARCAM_SANITIZED
  if (!test::long_tests()) GTEST_SKIP() << "checked in the normal build";
#endif
  const Job job = load_job(example("witch_grinding"));
  PlacementOptions o = job.optimize;
  o.threads = 2;
  const PoleProblem p = job_pole_problem(job, o, true);
  const ParetoResult r = pareto_front(p, job.placement, o);
  std::vector<const ParetoPoint*> levels;
  for (const ParetoPoint& x : r.front)
    if (x.source.rfind("level", 0) == 0) levels.push_back(&x);
  ASSERT_GE(levels.size(), 2u) << "the levels' searches should reach the front";
  const SearchBox box = search_box(p);
  const int n = 33;
  const double hx = (box.x1 - box.x0) / (n - 1), hy = (box.y1 - box.y0) / (n - 1);
  for (const ParetoPoint* x : {levels.front(), levels.back()}) {
    const double limit = x->v.torque.worst;
    auto area_within = [&](const PoleValue& v) {
      if (!v.feasible() || !v.torque_computed || !v.torque.computed || !(v.torque.worst <= limit))
        return std::numeric_limits<double>::infinity();
      return v.area_m2;
    };
    // the coarse grid's best within the limit, refined around it; where no pole of the grid is within the limit (a
    // level next to the least torque, whose region is smaller than a cell), the refinement around the level's own
    // pole, which is within it
    const test::DenseBest coarse = test::dense_search(p, box, n, area_within);
    const Vec2 c = std::isfinite(coarse.value) ? coarse.pole : x->pole;
    const test::DenseBest fine = test::dense_search(p, {c.x - hx, c.x + hx, c.y - hy, c.y + hy}, 21, area_within);
    ASSERT_TRUE(std::isfinite(fine.value)) << x->source << ": no pole near the level is within its limit";
    const double best = std::min(coarse.value, fine.value);
    EXPECT_GE(best, 0.99 * x->v.area_m2) << x->source << " (worst ratio " << limit << "): front " << x->v.area_m2 * 1e6
                                         << " mm^2, dense " << best * 1e6 << " mm^2";
  }
}

// The least area error within the torque limit (`optimize --objective area --torque-limit`, the operator's report's
// third placement): its search box comes from the work area alone, the limit checked where the search evaluates; an
// independent dense search of the least area error among the poles whose every ratio is within the limit finds
// nothing more than 1 % better. The witch with the grinding load (NO-GO at its own pole); under the sanitizers only
// with POLARCAM_LONG_TESTS=1.
TEST(TorqueLimitedArea, NoDenseSearchFindsMoreThanOnePercentBetter) {
#ifdef POLARCAM_SANITIZED
  if (!test::long_tests()) GTEST_SKIP() << "checked in the normal build";
#endif
  const Job job = load_job(example("witch_grinding"));
  PlacementOptions o = job.optimize;
  o.objective = PoleObjective::area;
  o.torque_limit = true;
  o.threads = 2;
  const PoleProblem p = job_pole_problem(job, o, true);
  ASSERT_TRUE(p.torque_limit.has_value());
  const double limit = *p.torque_limit;
  EXPECT_NEAR(limit, 1.0 / 1.2, 1e-12);
  const PlacementResult r = optimize_placement(p, job.placement, o);
  ASSERT_TRUE(r.at.feasible());
  ASSERT_TRUE(r.at.torque_computed && r.at.torque.computed);
  EXPECT_LE(r.at.torque.worst, limit);
  ASSERT_GE(r.at.area_m2, 0.0);
  auto area_within = [&](const PoleValue& v) {
    if (!v.feasible() || !v.torque_computed || !v.torque.computed || !(v.torque.worst <= limit) ||
        !(v.torque.rate_over <= 1.0))
      return std::numeric_limits<double>::infinity();
    return v.area_m2;
  };
  const SearchBox box = search_box(p);
  const int n = 33;
  const double hx = (box.x1 - box.x0) / (n - 1), hy = (box.y1 - box.y0) / (n - 1);
  const test::DenseBest coarse = test::dense_search(p, box, n, area_within);
  ASSERT_TRUE(std::isfinite(coarse.value));
  const test::DenseBest fine = test::dense_search(
      p, {coarse.pole.x - hx, coarse.pole.x + hx, coarse.pole.y - hy, coarse.pole.y + hy}, 21, area_within);
  const double best = std::min(coarse.value, fine.value);
  EXPECT_GE(best, 0.99 * r.at.area_m2) << "found " << r.at.area_m2 * 1e6 << " mm^2 at (" << r.pole.x << ", "
                                       << r.pole.y << "), dense " << best * 1e6 << " mm^2";
}

// The searches analyse the path at fewer samples (search_analysis: 1000 along the path) than `analyze` (4000), since
// the maxima are refined between samples. At a 9 x 9 lattice of poles over each job's feasible box, every maximum a
// search reads (both torque ratios, their sum, the balanced objective, the step-rate excess) agrees with the one at
// `analyze`'s sampling and with one at five times it, to 1e-9. (Under the sanitizers two jobs, unless
// POLARCAM_LONG_TESTS=1.)
TEST(SearchSampling, MaximaAgreeWithTheDefaultSamplingAcrossTheFeasiblePoles) {
  for (const std::string name : {"circle_inertial", "witch_grinding", "circle_grinding", "witch_inertial",
                                 "limacon_inertial", "limacon_grinding", "serpentine_inertial", "serpentine_grinding"}) {
#ifdef POLARCAM_SANITIZED
    if (!test::long_tests() && name != "circle_inertial" && name != "witch_grinding") continue;
#endif
    const Job job = load_job(example(name));
    PlacementOptions o = job.optimize;
    o.objective = PoleObjective::balanced;
    const PoleProblem p = job_pole_problem(job, o, true);
    ASSERT_TRUE(p.torque);
    ASSERT_EQ(p.torque->options.target_samples, search_analysis().target_samples);
    auto with = [&](int samples) {
      PoleProblem q = p;
      AnalysisOptions a;
      a.target_samples = samples;
      q.torque = make_torque_problem(p.torque->machine, p.torque->setup, p.torque->side, a);
      return q;
    };
    const PoleProblem p_default = with(AnalysisOptions{}.target_samples), p_fine = with(20000);
    const SearchBox box = feasible_box(p, search_box(p), 41, 2);
    std::vector<Vec2> poles;
    const int n = 9;
    for (int iy = 0; iy < n; ++iy)
      for (int ix = 0; ix < n; ++ix)
        poles.push_back({box.x0 + (box.x1 - box.x0) * ix / (n - 1), box.y0 + (box.y1 - box.y0) * iy / (n - 1)});
    const std::vector<PoleValue> vs = evaluate_poles(p, poles, 2), vd = evaluate_poles(p_default, poles, 2),
                                 vf = evaluate_poles(p_fine, poles, 2);
    int compared = 0;
    for (size_t i = 0; i < poles.size(); ++i) {
      if (!vs[i].feasible() || !vs[i].torque_computed) continue;
      for (const PoleValue* other : {&vd[i], &vf[i]}) {
        ASSERT_TRUE(other->torque_computed) << name << " pole " << i;
        const TorqueValue &a = vs[i].torque, &b = other->torque;
        ASSERT_EQ(a.computed, b.computed) << name << " pole " << i;
        if (!a.computed) continue;
        auto close = [](double x, double y, double tol = 1e-9) {
          return x == y || std::abs(x - y) <= tol * std::max(std::abs(x), std::abs(y));
        };
        EXPECT_TRUE(close(a.ratio_radial, b.ratio_radial)) << name << " pole " << i << ": " << a.ratio_radial << " " << b.ratio_radial;
        EXPECT_TRUE(close(a.ratio_angular, b.ratio_angular)) << name << " pole " << i << ": " << a.ratio_angular << " " << b.ratio_angular;
        EXPECT_TRUE(close(a.ratio_sum, b.ratio_sum)) << name << " pole " << i << ": " << a.ratio_sum << " " << b.ratio_sum;
        EXPECT_TRUE(close(a.balanced, b.balanced, 1e-7)) << name << " pole " << i << ": " << a.balanced << " " << b.balanced;
        EXPECT_TRUE(close(a.rate_over, b.rate_over)) << name << " pole " << i << ": " << a.rate_over << " " << b.rate_over;
        EXPECT_EQ(a.go, b.go) << name << " pole " << i;
      }
      ++compared;
    }
    EXPECT_GE(compared, 20) << name;
  }
}

}  // namespace tu_pipeline_test_optimum_loading
