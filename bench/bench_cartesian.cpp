// Cartesian machine throughput (steps per CPU-second, one core) on the thesis's limacon (no placement: the
// contour's own frame) at the thesis resolution (0.001 in) and 100x finer:
//  - Exact: build the Cartesian track and step it at exact times;
//  - Dda: fit lines and arcs (tolerance BLU / 4), make the DDA program and run the interpolator (5 kHz clock at
//    the thesis resolution; a clock fast enough for the feed at the finer one);
//  - DdaRunOnly: the interpolator alone on a prepared program;
//  - ArcFit: the lines-and-arcs approximation alone (segments per second).
#include <benchmark/benchmark.h>

#include "cam/arc_fit.hpp"
#include "cam/curves.hpp"
#include "cam/toolpath.hpp"
#include "machine/cartesian/cartesian_exact.hpp"
#include "machine/cartesian/dda.hpp"

using namespace polarcam;

namespace {

constexpr double kSpeed = 0.0152;  // the thesis's 1.52 cm/s

ToolPathPtr limacon() { return make_tool_path(make_limacon(0.0508, 0.0762), Placement{}, ToolSpec{}, TravelSpec{}); }

void rate(benchmark::State& state, uint64_t per_iteration, const char* what) {
  state.counters[what] = static_cast<double>(per_iteration);
  state.counters[std::string(what) + "_per_s"] = benchmark::Counter(
      static_cast<double>(per_iteration) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

DdaProgram program(const Curve& path, double blu) {
  ArcFitOptions fo;
  fo.tolerance = blu / 4;
  ArcFit fit = fit_lines_and_arcs(path, fo);
  DdaOptions o;
  o.interrupt_hz = std::max(5000.0, 2.0 * kSpeed / blu);
  return make_dda_program(fit.segments, path.closed(), blu, kSpeed, o);
}

}  // namespace

// Runs `step` (which returns a CartesianResult) once per iteration and reports its steps.
template <class F>
void steps_per_second(benchmark::State& state, F step) {
  uint64_t steps = 0;
  for (auto _ : state) {
    CartesianResult r = step();
    steps = r.steps();
    benchmark::DoNotOptimize(r);
  }
  rate(state, steps, "steps");
}

double blu_of(const benchmark::State& state) { return 0.0254e-3 / static_cast<double>(state.range(0)); }

static void BM_Exact(benchmark::State& state) {
  auto path = limacon();
  const double blu = blu_of(state);
  steps_per_second(state, [&] {
    CartesianTrack tr = CartesianTrack::build(*path);
    auto prof = make_constant_speed(kSpeed, tr.length());
    return step_exact(tr, blu, *prof, nullptr);
  });
}

static void BM_Dda(benchmark::State& state) {
  auto path = limacon();
  const double blu = blu_of(state);
  steps_per_second(state, [&] { return run_dda(program(*path, blu), nullptr); });
}

static void BM_DdaRunOnly(benchmark::State& state) {
  const DdaProgram p = program(*limacon(), blu_of(state));
  steps_per_second(state, [&] { return run_dda(p, nullptr); });
}

static void BM_ArcFit(benchmark::State& state) {
  auto path = limacon();
  ArcFitOptions fo;
  fo.tolerance = 0.0254e-3 / static_cast<double>(state.range(0)) / 4;
  uint64_t segs = 0;
  for (auto _ : state) {
    ArcFit f = fit_lines_and_arcs(*path, fo);
    segs = f.segments.size();
    benchmark::DoNotOptimize(f);
  }
  rate(state, segs, "segments");
}

BENCHMARK(BM_Exact)->Arg(1)->Arg(100)->ArgName("finer")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Dda)->Arg(1)->Arg(100)->ArgName("finer")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DdaRunOnly)->Arg(1)->Arg(100)->ArgName("finer")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ArcFit)->Arg(1)->Arg(100)->ArgName("finer")->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
