// `polarcam analyze` on a job of about 10^6 steps (the target: under a second): the limacon of the thesis
// at its pole of minimum area error (examples/ch5/limacon_area.toml, ground at Table 5.1's conditions) on a grid
// 46 times finer than the prototype's, which makes its tape 1.01 million steps long.
//  - BM_AnalyzeJob: what the command does after reading the job: build the path and its polar track, check the work
//    area, analyse the torques (default sampling, series kept for --csv/--plot), judge, and search the fastest
//    passing speed.
//  - BM_AnalyzeJobPerStep: the same analysis sampled about once per step (spacing = the grid's step length), no
//    speed search: the cost per sample.
//  - BM_Objective: the analysis as an optimiser's objective (maxima only) at the prototype's grid.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <string>

#include "pipeline/job_analysis.hpp"
#include "pipeline/job_tape.hpp"

using namespace polarcam;

namespace {

constexpr int kFiner = 46;

Job fine_job() {
  Job job = load_job(std::string(POLARCAM_SOURCE_DIR) + "/examples/ch5/limacon_area.toml");
  job.machine.grid.dr /= kFiner;
  job.machine.grid.steps_per_rev *= kFiner;
  job.machine.grid.dtheta = dtheta_from_steps(job.machine.grid.steps_per_rev);
  return job;
}

uint64_t steps_of(const Job& job) {
  DigitizedJob d = digitize_job(job, nullptr);
  return d.result.radial.steps() + d.result.angular.steps();
}

void BM_AnalyzeJob(benchmark::State& state) {
  const Job job = fine_job();
  size_t samples = 0;
  for (auto _ : state) {
    PreparedDynamics prep = prepare_dynamics(job);
    CaseResult r = analyze_case(job, prep, DynamicsCase{std::nullopt, job.load}, AnalysisOptions{});
    samples = r.analysis.samples;
    benchmark::DoNotOptimize(r);
  }
  state.counters["steps"] = static_cast<double>(steps_of(job));
  state.counters["samples"] = static_cast<double>(samples);
}

void BM_AnalyzeJobPerStep(benchmark::State& state) {
  const Job job = fine_job();
  AnalysisOptions opt;
  opt.spacing = std::min(job.machine.grid.dr, 0.0381 * job.machine.grid.dtheta);  // the step length at the path's smallest r
  size_t samples = 0;
  for (auto _ : state) {
    PreparedDynamics prep = prepare_dynamics(job);
    CaseResult r = analyze_case(job, prep, DynamicsCase{std::nullopt, job.load}, opt, false);
    samples = r.analysis.samples;
    benchmark::DoNotOptimize(r);
  }
  state.counters["steps"] = static_cast<double>(steps_of(job));
  state.counters["samples"] = static_cast<double>(samples);
  state.counters["samples_per_s"] = benchmark::Counter(
      static_cast<double>(samples) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_Objective(benchmark::State& state) {
  const Job job = load_job(std::string(POLARCAM_SOURCE_DIR) + "/examples/ch5/limacon_area.toml");
  const PreparedDynamics prep = prepare_dynamics(job);
  AnalysisOptions opt;
  opt.keep_series = false;
  for (auto _ : state) {
    CaseResult r = analyze_case(job, prep, DynamicsCase{std::nullopt, job.load}, opt, false);
    benchmark::DoNotOptimize(r);
  }
}

}  // namespace

BENCHMARK(BM_AnalyzeJob)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AnalyzeJobPerStep)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Objective)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
