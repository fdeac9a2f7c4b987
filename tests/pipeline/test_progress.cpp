// Progress of long work: every library function that takes a Progress calls it with fractions that never
// decrease, from near 0 to exactly 1, on the thread(s) doing the work, whatever the number of threads.
#include <gtest/gtest.h>

#include <mutex>
#include <string>
#include <vector>

#include "io/progress.hpp"
#include "job/job.hpp"
#include "optimize/pareto.hpp"
#include "optimize/placement.hpp"
#include "pipeline/compare.hpp"
#include "pipeline/job_analysis.hpp"
#include "pipeline/job_export.hpp"
#include "pipeline/job_placement.hpp"
#include "pipeline/job_study.hpp"
#include "pipeline/job_tape.hpp"

namespace polarcam {
namespace tu_pipeline_test_progress {  // named: the test files compile together

// Records every call (from any thread).
struct Recorder {
  std::mutex m;
  std::vector<double> f;
  Progress fn() {
    return [this](double x) {
      std::lock_guard<std::mutex> lk(m);
      f.push_back(x);
    };
  }
  // at least `calls` calls, the first below `first_below`, never decreasing, within [0, 1], the last 1
  void check(const std::string& what, size_t calls = 2, double first_below = 0.5) {
    ASSERT_GE(f.size(), calls) << what;
    EXPECT_LT(f.front(), first_below) << what;
    for (size_t i = 0; i < f.size(); ++i) {
      EXPECT_GE(f[i], 0.0) << what << " call " << i;
      EXPECT_LE(f[i], 1.0) << what << " call " << i;
      if (i > 0) {
        EXPECT_GE(f[i], f[i - 1]) << what << " call " << i;
      }
    }
    EXPECT_EQ(f.back(), 1.0) << what;
  }
};

Job example(const std::string& name) { return load_job(std::string(POLARCAM_SOURCE_DIR) + "/examples/" + name); }

TEST(Progress, DigitizeJobFollowsThePathsTime) {
  Recorder r;
  digitize_job(example("limacon.toml"), nullptr, r.fn());  // 22 000 steps: a report every 4096
  r.check("digitize_job", 5, 0.5);
}

TEST(Progress, ExportJobReportsItsStages) {
  Recorder r;
  ExportOptions o;
  o.format = ExportFormat::svg;
  export_job(example("witch.toml"), o, r.fn());
  r.check("export_job", 3, 0.01);
}

TEST(Progress, AnalyzeCaseStartsAtZeroAndEndsAtOne) {
  const Job job = example("ch5/circle.toml");
  const PreparedDynamics prep = prepare_dynamics(job);
  Recorder r;
  analyze_case(job, prep, DynamicsCase{std::nullopt, job.load}, AnalysisOptions{}, true, r.fn());
  r.check("analyze_case", 2, 0.01);
}

TEST(Progress, CompareJobCoversBothMachines) {
  Recorder r;
  compare_job(example("testpiece_diamond.toml"), CompareOptions{}, r.fn());
  r.check("compare_job", 4, 0.3);
}

TEST(Progress, PoleGridsCountTheirPolesOnEveryThread) {
  const Job job = example("ch6/circle_inertial.toml");
  PlacementOptions po = job.optimize;
  po.objective = PoleObjective::area;
  const PoleProblem prob = job_pole_problem(job, po, true);
  const SearchBox box = search_box(prob);
  for (int threads : {1, 3}) {
    const std::string t = " on " + std::to_string(threads) + " threads";
    Recorder a, b, c, d;
    feasible_box(prob, box, 6, threads, a.fn());
    a.check("feasible_box" + t, 36, 0.05);
    objective_map(prob, box, 4, 4, threads, b.fn());
    b.check("objective_map" + t, 16, 0.1);
    survey_poles(prob, box, 4, 4, threads, c.fn());
    c.check("survey_poles" + t, 16, 0.1);
    evaluate_poles(prob, {job.placement.pole(), {0.01, 0.0}, {0.0, 0.01}}, threads, d.fn());
    d.check("evaluate_poles" + t, 3, 0.5);
  }
}

TEST(Progress, PlacementAndParetoSearchesSpendTheirBudget) {
  const Job job = example("ch6/circle_inertial.toml");
  PlacementOptions po = job.optimize;
  po.objective = PoleObjective::area;
  po.max_evaluations = 20;
  po.threads = 2;
  const PoleProblem prob = job_pole_problem(job, po, true);
  Recorder a;
  optimize_placement(prob, job.placement, po, a.fn());
  a.check("optimize_placement", 3, 0.5);
  ParetoOptions pa;
  pa.survey = 4;
  pa.levels = 1;
  pa.threads = 2;
  Recorder b;
  pareto_front(prob, job.placement, po, pa, b.fn());
  b.check("pareto_front", 10, 0.1);
}

TEST(Progress, StudyJobGoesThroughEveryPart) {
  StudyOptions o;
  o.map_size = 4;
  o.max_evaluations = 20;
  o.curve_points = 2;
  o.threads = 2;
  Recorder r;
  study_job(example("ch6/circle_inertial.toml"), o, r.fn());
  r.check("study_job", 10, 0.2);
}

}  // namespace tu_pipeline_test_progress
}  // namespace polarcam
