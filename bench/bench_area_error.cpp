// (benchmark::DoNotOptimize is not used on doubles: with GCC 12 and Debian's libbenchmark 1.7 it corrupts them.)
// Area-error throughput (steps per second, one core) on the Table 4.1 contours at the thesis's resolution
// (0.001 in, 16000 steps per revolution), each at the thesis's optimum pole:
//  - BM_AreaError: the meter alone, over a staircase recorded beforehand (reset, record every step, finish);
//  - BM_AreaError/fine: the same contours on a grid 10x finer in both axes (the limacon also 100x);
//  - BM_AreaErrorStreamed: the meter in its streamed mode (begin(), constant memory), the same staircases;
//  - BM_ErrorMetersStreamed: the area and the deviation together as `polarcam error` runs them (ErrorMeters in
//    the streamed mode: area, deviation, F_sum/F_dif step counts), the same staircases, the limacon also 100x;
//  - BM_DigitizeAndArea: one evaluation of the optimiser as it was (track, digitize into the meter, finish);
//  - BM_TrackAndImpliedArea: one evaluation as it is (track, the nearest staircase from the meter's walk, finish);
//  - BM_CartesianAreaError: the Cartesian meter (metrics/cartesian_error.hpp) alone over the exact Cartesian
//    generator's staircase of the same contours in their own frames, BLU = 0.001 in and 10x finer;
//  - BM_CartesianDeviation: the deviation of the same staircases (DeviationMeter: three foot points a step).
#include <benchmark/benchmark.h>

#include <numbers>
#include <vector>

#include "cam/curves.hpp"
#include "cam/toolpath.hpp"
#include "bench/thesis_grid.hpp"
#include "digitizer/digitize.hpp"
#include "machine/cartesian/cartesian_exact.hpp"
#include "metrics/area_error.hpp"
#include "metrics/cartesian_error.hpp"
#include "metrics/error_metrics.hpp"

using namespace polarcam;

namespace {

using bench::thesis_grid;

ToolPathPtr contour(int which) {
  switch (which) {
    case 0: return make_tool_path(make_witch(0.2159, -0.2032, 0.2032), Placement{0.1546, 1.236}, {}, {});
    case 1: return make_tool_path(make_limacon(0.0508, 0.0762), Placement{0.0127, 0.0}, {}, {});
    default: return make_tool_path(make_serpentine(0.0127, 0.0762, -0.0762, 0.0762), Placement{0.0537, 4.247}, {}, {});
  }
}
const char* kNames[] = {"witch", "limacon", "serpentine"};

struct Step {
  int8_t axis, dir;
};
class Recorder : public StepSink {
 public:
  void step(int axis, int dir, int64_t) override { steps.push_back({static_cast<int8_t>(axis), static_cast<int8_t>(dir)}); }
  std::vector<Step> steps;
};

// The staircase the benchmarks measure: contour `which` digitized on the thesis grid `finer` times finer at
// 0.0152 m/s, its steps recorded (the track and grid the meter binds to kept beside them).
struct Staircase {
  ToolPathPtr path;
  Grid g;
  PolarTrack tr;
  DigitizeResult d;
  Recorder rec;
};
Staircase staircase(int which, double finer) {
  Staircase s{contour(which), thesis_grid(finer), {}, {}, {}};
  s.tr = PolarTrack::build(*s.path);
  auto prof = make_constant_speed(0.0152, s.tr.length());
  s.d = digitize(s.tr, s.g, StepRule::nearest, *prof, &s.rec);
  return s;
}

void BM_AreaError(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const auto [path, g, tr, d, rec] = staircase(which, static_cast<double>(state.range(1)));
  PolarAreaMeter meter;
  double area = 0;
  for (auto _ : state) {
    meter.reset(tr, g);
    for (const Step& s : rec.steps) meter.record(s.axis, s.dir);
    area = meter.finish(d.start_n, d.start_m).area_m2;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(rec.steps.size()));
  state.SetLabel(std::string(kNames[which]) + ", " + std::to_string(rec.steps.size()) + " steps, area " +
                 std::to_string(area * 1e6) + " mm^2");
}
BENCHMARK(BM_AreaError)->ArgsProduct({{0, 1, 2}, {1, 10}})->Unit(benchmark::kMillisecond);

// The streamed meter (begin() with the start node, each sector measured once the staircase and the contour have
// moved on): the same staircases, and the limacon on a grid 100x finer (2.2 M steps). The label gives the most
// sectors held at once.
void BM_AreaErrorStreamed(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const auto [path, g, tr, d, rec] = staircase(which, static_cast<double>(state.range(1)));
  PolarAreaMeter meter;
  double area = 0;
  bool streamed = true;
  for (auto _ : state) {
    meter.reset(tr, g);
    meter.stream_from(d.start_n, d.start_m);
    for (const Step& s : rec.steps) meter.record(s.axis, s.dir);
    area = meter.finish(d.start_n, d.start_m).area_m2;
    streamed = streamed && meter.streamed();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(rec.steps.size()));
  state.SetLabel(std::string(kNames[which]) + ", " + std::to_string(rec.steps.size()) + " steps, area " +
                 std::to_string(area * 1e6) + " mm^2, " + std::to_string(meter.peak_window()) + " sectors held" +
                 (streamed ? "" : ", NOT STREAMED"));
}
BENCHMARK(BM_AreaErrorStreamed)->ArgsProduct({{0, 1, 2}, {1, 10}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AreaErrorStreamed)->Args({1, 100})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AreaError)->Args({1, 100})->Unit(benchmark::kMillisecond);

// ErrorMeters streamed, as `polarcam error` feeds it from a tape (without reading the tape): the label gives the
// area and the deviation.
void BM_ErrorMetersStreamed(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const auto [path, g, tr, d, rec] = staircase(which, static_cast<double>(state.range(1)));
  ErrorMeters em;
  ErrorMetrics m;
  bool streamed = true;
  for (auto _ : state) {
    em.reset(*path, tr, g, 100);
    em.stream_from(d.start_n, d.start_m);
    for (const Step& s : rec.steps) em.record(s.axis, s.dir);
    m = em.finish(d.start_n, d.start_m);
    streamed = streamed && em.streamed();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(rec.steps.size()));
  state.SetLabel(std::string(kNames[which]) + ", " + std::to_string(rec.steps.size()) + " steps, area " +
                 std::to_string(m.area.area_m2 * 1e6) + " mm^2, deviation " + std::to_string(m.deviation_max_m * 1e3) +
                 " mm" + (streamed ? "" : ", NOT STREAMED"));
}
BENCHMARK(BM_ErrorMetersStreamed)->ArgsProduct({{0, 1}, {1, 10}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ErrorMetersStreamed)->Args({1, 100})->Unit(benchmark::kMillisecond);

void BM_DigitizeAndArea(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  auto path = contour(which);
  Grid g = thesis_grid(1.0);
  PolarAreaMeter meter;
  uint64_t steps = 0;
  double area = 0;
  for (auto _ : state) {
    PolarTrack tr = PolarTrack::build(*path);
    auto prof = make_constant_speed(0.0152, tr.length());
    meter.reset(tr, g);
    DigitizeResult d = digitize(tr, g, StepRule::nearest, *prof, &meter);
    AreaErrorResult a = meter.finish(d.start_n, d.start_m);
    steps = a.rise_steps + a.run_steps;
    area = a.area_m2;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * steps));
  state.SetLabel(std::string(kNames[which]) + ", area " + std::to_string(area * 1e6) + " mm^2");
}
BENCHMARK(BM_DigitizeAndArea)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

// What one evaluation of the pole search costs now: the track, the nearest rule's staircase read off the meter's
// walk (imply_nearest; the digitizer where it refuses), finish. The label says how many were refused.
void BM_TrackAndImpliedArea(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  auto path = contour(which);
  Grid g = thesis_grid(1.0);
  PolarAreaMeter meter;
  uint64_t steps = 0, refused = 0;
  double area = 0;
  for (auto _ : state) {
    PolarTrack tr = PolarTrack::build(*path);
    const auto n0 = start_node(tr, g, StepRule::nearest);
    meter.reset(tr, g);
    AreaErrorResult a;
    if (meter.imply_nearest(n0[0], n0[1])) {
      a = meter.finish(n0[0], n0[1]);
    } else {
      ++refused;
      auto prof = make_constant_speed(0.0152, tr.length());
      meter.reset(tr, g);
      DigitizeResult d = digitize(tr, g, StepRule::nearest, *prof, &meter);
      a = meter.finish(d.start_n, d.start_m);
    }
    steps = a.rise_steps + a.run_steps;
    area = a.area_m2;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * steps));
  state.SetLabel(std::string(kNames[which]) + ", area " + std::to_string(area * 1e6) + " mm^2" +
                 (refused ? ", " + std::to_string(refused) + " refused" : std::string()));
}
BENCHMARK(BM_TrackAndImpliedArea)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

ToolPathPtr own_frame(int which) {
  switch (which) {
    case 0: return make_tool_path(make_witch(0.2159, -0.2032, 0.2032), Placement{}, {}, {});
    case 1: return make_tool_path(make_limacon(0.0508, 0.0762), Placement{}, {}, {});
    default: return make_tool_path(make_serpentine(0.0127, 0.0762, -0.0762, 0.0762), Placement{}, {}, {});
  }
}

struct CartesianStairs {
  ToolPathPtr path;
  CartesianTrack track;
  CartesianResult res;
  Recorder rec;
};

CartesianStairs cartesian_stairs(int which, double blu) {
  CartesianStairs c;
  c.path = own_frame(which);
  c.track = CartesianTrack::build(*c.path);
  auto prof = make_constant_speed(0.0152, c.track.length());
  c.res = step_exact(c.track, blu, *prof, &c.rec);
  return c;
}

void BM_CartesianAreaError(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const double blu = 0.0254e-3 / static_cast<double>(state.range(1));
  CartesianStairs c = cartesian_stairs(which, blu);
  CartesianAreaMeter meter;
  double area = 0;
  for (auto _ : state) {
    meter.reset(c.track, blu);
    for (const Step& s : c.rec.steps) meter.record(s.axis, s.dir);
    area = meter.finish(c.res.start[0], c.res.start[1]).area_m2;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(c.rec.steps.size()));
  state.SetLabel(std::string(kNames[which]) + ", " + std::to_string(c.rec.steps.size()) + " steps, area " +
                 std::to_string(area * 1e6) + " mm^2");
}
BENCHMARK(BM_CartesianAreaError)->ArgsProduct({{0, 1, 2}, {1, 10}})->Unit(benchmark::kMillisecond);

void BM_CartesianDeviation(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const double blu = 0.0254e-3;
  CartesianStairs c = cartesian_stairs(which, blu);
  CartesianErrorMeters em;
  double dev = 0;
  for (auto _ : state) {
    em.reset(*c.path, c.track, blu);
    for (const Step& s : c.rec.steps) em.record(s.axis, s.dir);
    dev = em.finish(c.res.start[0], c.res.start[1]).deviation_max_m;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(c.rec.steps.size()));
  state.SetLabel(std::string(kNames[which]) + ", deviation " + std::to_string(dev * 1e3) + " mm");
}
BENCHMARK(BM_CartesianDeviation)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
