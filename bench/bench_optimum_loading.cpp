// Optimum loading (docs/optimum-loading.md) on the examples/ch6 jobs at the prototype's grid:
//  - BM_BalancedPole: one evaluation of the balanced objective at a pole (track of the moved path + the analysis of
//    `analyze`, maxima only): the unit of cost of every torque search;
//  - BM_BalancedSearch: `optimize --objective balanced` (default budget, 2000 evaluations) on one thread and on all;
//  - BM_Capacity: `capacity` (largest speed, largest load) at the job's pole.
#include <benchmark/benchmark.h>

#include <string>

#include "job/job.hpp"
#include "pipeline/job_analysis.hpp"
#include "pipeline/job_capacity.hpp"
#include "pipeline/job_placement.hpp"
#include "optimize/placement.hpp"

using namespace polarcam;

namespace {

const char* kJobs[] = {"circle_inertial", "witch_grinding", "limacon_inertial", "serpentine_grinding"};

Job job_of(int i) {
  return load_job(std::string(POLARCAM_SOURCE_DIR) + "/examples/ch6/" + kJobs[i] + ".toml");
}

void BM_BalancedPole(benchmark::State& state) {
  const Job job = job_of(static_cast<int>(state.range(0)));
  PlacementOptions o = job.optimize;
  o.objective = PoleObjective::balanced;
  const PoleProblem p = job_pole_problem(job, o, true);
  PoleEvaluator ev(p);
  const Vec2 pole = job.placement.pole();
  for (auto _ : state) benchmark::DoNotOptimize(ev.evaluate(pole));
  state.SetLabel(kJobs[state.range(0)]);
}

void BM_BalancedSearch(benchmark::State& state) {
  const Job job = job_of(static_cast<int>(state.range(0)));
  PlacementOptions o = job.optimize;
  o.objective = PoleObjective::balanced;
  o.threads = static_cast<int>(state.range(1));
  const PoleProblem p = job_pole_problem(job, o, true);
  int evals = 0;
  for (auto _ : state) {
    const PlacementResult r = optimize_placement(p, job.placement, o);
    evals = r.evaluations;
    benchmark::DoNotOptimize(r);
  }
  state.counters["evaluations"] = evals;
  state.SetLabel(std::string(kJobs[state.range(0)]) + ", threads " + std::to_string(state.range(1)));
}

void BM_Capacity(benchmark::State& state) {
  const Job job = job_of(static_cast<int>(state.range(0)));
  const PreparedDynamics prep = prepare_dynamics(job);
  int evals = 0;
  for (auto _ : state) {
    const JobCapacity c = job_capacity(job, prep, std::nullopt, 0);
    evals = c.speed_cap.evaluations + c.load_cap.evaluations;
    benchmark::DoNotOptimize(c);
  }
  state.counters["analyses"] = evals;
  state.SetLabel(kJobs[state.range(0)]);
}

}  // namespace

BENCHMARK(BM_BalancedPole)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BalancedSearch)->ArgsProduct({{0, 1, 2, 3}, {1, 2}})->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_Capacity)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
