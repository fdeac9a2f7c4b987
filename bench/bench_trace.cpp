// Tracing template images (cam/image_trace): a 4000 x 4000 scan of 150 disks (a drawn template at 0.05 mm per
// pixel: 20 cm square) traced into contours; and the reading of the same image as a raw PGM.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>

#include "cam/image_trace.hpp"

using namespace polarcam;

namespace {

GrayImage disks(int n) {
  GrayImage im;
  im.width = im.height = n;
  im.luminance.assign(static_cast<size_t>(n) * n, 255);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> pos(0, n), rad(0.005 * n, 0.05 * n);
  for (int k = 0; k < 150; ++k) {
    const double cx = pos(rng), cy = pos(rng), r = rad(rng);
    for (int j = std::max(0, int(cy - r)); j < std::min(n, int(cy + r) + 1); ++j) {
      const double dy = j + 0.5 - cy;
      if (std::abs(dy) > r) continue;
      const double dx = std::sqrt(r * r - dy * dy);
      for (int i = std::max(0, int(cx - dx)); i < std::min(n, int(cx + dx)); ++i) im.luminance[size_t(j) * n + i] = 0;
    }
  }
  return im;
}

void BM_Trace(benchmark::State& state) {
  const GrayImage im = disks(static_cast<int>(state.range(0)));
  TraceOptions o;
  o.pixel_size_m = 5e-5;
  size_t contours = 0;
  for (auto _ : state) {
    const Tracing t = trace_image(im, o, "disks");
    contours = t.contours.size();
    benchmark::DoNotOptimize(contours);
  }
  state.counters["contours"] = static_cast<double>(contours);
  state.counters["Mpixel/s"] = benchmark::Counter(double(im.width) * im.height * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Trace)->Arg(1000)->Arg(4000)->Unit(benchmark::kMillisecond);

void BM_ReadPgm(benchmark::State& state) {
  const GrayImage im = disks(4000);
  std::string bytes = "P5 4000 4000 255\n";
  bytes.append(im.luminance.begin(), im.luminance.end());
  for (auto _ : state) benchmark::DoNotOptimize(parse_image(bytes, "disks.pgm").width);
}
BENCHMARK(BM_ReadPgm)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
