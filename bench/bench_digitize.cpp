// Digitizing throughput (steps per second, one core): the limacon of the thesis at the thesis resolution and at
// 100x finer resolution, and a closed cubic spline through 10^4 points. Each iteration builds the polar track and
// digitizes it; variants with "/tape" also write the step tape to a temporary file.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <unistd.h>

#include "cam/curves.hpp"
#include "cam/spline.hpp"
#include "cam/toolpath.hpp"
#include "bench/thesis_grid.hpp"
#include "digitizer/digitize.hpp"
#include "digitizer/tape.hpp"

using namespace polarcam;

namespace {

using bench::thesis_grid;

ToolPathPtr limacon_path() {
  return make_tool_path(make_limacon(0.0508, 0.0762), Placement{0.0127, 0.0}, ToolSpec{}, TravelSpec{});
}

ToolPathPtr spline_path(int n) {
  std::vector<Vec2> pts;
  for (int i = 0; i < n; ++i) {
    double t = 2 * std::numbers::pi * i / n, r = 0.0762 + 0.0508 * std::cos(t) + 0.004 * std::sin(7 * t);
    pts.push_back({r * std::cos(t), r * std::sin(t)});
  }
  return make_tool_path(make_spline(pts, true, "bench"), Placement{0.0127, 0.0}, ToolSpec{}, TravelSpec{});
}

void run(benchmark::State& state, const ToolPathPtr& path, double finer, bool tape) {
  Grid g = thesis_grid(finer);
  uint64_t steps = 0;
  std::string file = "/tmp/polarcam-bench-" + std::to_string(::getpid()) + ".tape";
  for (auto _ : state) {
    PolarTrack tr = PolarTrack::build(*path);
    auto prof = make_constant_speed(0.0152, tr.length());
    DigitizeResult r;
    if (tape) {
      TapeHeader h;
      h.res[0] = g.dr;
      h.res[1] = g.dtheta;
      TapeWriter w(file, h);
      r = digitize(tr, g, StepRule::nearest, *prof, &w);
      h.start[0] = r.start_n;
      h.start[1] = r.start_m;
      h.end[0] = r.end_n;
      h.end[1] = r.end_m;
      w.finish(h);
    } else {
      r = digitize(tr, g, StepRule::nearest, *prof, nullptr);
    }
    steps = r.radial.steps() + r.angular.steps();
    benchmark::DoNotOptimize(r);
  }
  std::remove(file.c_str());
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["steps_per_s"] =
      benchmark::Counter(static_cast<double>(steps) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

}  // namespace

static void BM_LimaconThesis(benchmark::State& s) { run(s, limacon_path(), 1.0, s.range(0)); }
static void BM_Limacon100x(benchmark::State& s) { run(s, limacon_path(), 100.0, s.range(0)); }
static void BM_Spline10k(benchmark::State& s) { run(s, spline_path(10000), 1.0, s.range(0)); }
static void BM_Spline10k100x(benchmark::State& s) { run(s, spline_path(10000), 100.0, s.range(0)); }
BENCHMARK(BM_LimaconThesis)->Arg(0)->Arg(1)->ArgName("tape")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Limacon100x)->Arg(0)->Arg(1)->ArgName("tape")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Spline10k)->Arg(0)->Arg(1)->ArgName("tape")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Spline10k100x)->Arg(0)->Arg(1)->ArgName("tape")->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
