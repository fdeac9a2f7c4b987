// A large sand-table pattern end to end, as `polarcam digitize` and `polarcam export` run it: a generated theta-rho
// file of 10^4, 10^5 or 10^6 vertices (tests/big_pattern.hpp: a spiral of 1000 vertices a turn, rho from the rim to
// the centre and back five times, half a turn of the arm at the centre each time, theta past 600 rad at 10^5) on
// the example sand table (coupled arm, 40 mm/s). Each iteration reads the pattern (import), digitizes it into a
// tape written to a temporary file (digitize), and exports it as G-code and as a theta-rho file (export).
// BM_PatternDigitize is the digitize part alone, the pattern read once.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>

#include "digitizer/tape.hpp"
#include "job/pattern.hpp"
#include "pipeline/job_export.hpp"
#include "pipeline/job_tape.hpp"
#include "tests/big_pattern.hpp"

using namespace polarcam;

namespace {

const std::string kTable = std::string(POLARCAM_SOURCE_DIR) + "/examples/machines/sand-table.toml";

struct TempPattern {
  std::string thr, tape;
  explicit TempPattern(size_t n) {
    const std::string base = "/tmp/polarcam-bench-pattern-" + std::to_string(::getpid()) + "-" + std::to_string(n);
    thr = base + ".thr";
    tape = base + ".tape";
    std::ofstream(thr) << test::thr_text(test::big_spiral_pattern(n));
  }
  ~TempPattern() {
    std::remove(thr.c_str());
    std::remove(tape.c_str());
  }
};

Job load(const std::string& thr) {
  PatternOptions o;
  o.machine_file = kTable;
  o.speed = 0.040;
  return load_job_or_pattern(thr, o);
}

uint64_t digitize_to_tape(const Job& job, const std::string& tape) {
  TapeHeader h = tape_header_for(job);
  TapeWriter w(tape, h);
  const DigitizedJob d = digitize_job(job, &w);
  complete_header(h, d.result);
  w.finish(h);
  return d.result.radial.steps() + d.result.angular.steps();
}

void BM_PatternEndToEnd(benchmark::State& state) {
  const TempPattern p(static_cast<size_t>(state.range(0)));
  uint64_t steps = 0;
  size_t bytes = 0;
  for (auto _ : state) {
    const Job job = load(p.thr);
    steps = digitize_to_tape(job, p.tape);
    ExportOptions o;
    o.format = ExportFormat::gcode;
    bytes = export_job(job, o).content.size();
    o.format = ExportFormat::thr;
    bytes += export_job(job, o).content.size();
    benchmark::DoNotOptimize(bytes);
  }
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["export_bytes"] = static_cast<double>(bytes);
}

void BM_PatternDigitize(benchmark::State& state) {
  const TempPattern p(static_cast<size_t>(state.range(0)));
  const Job job = load(p.thr);
  uint64_t steps = 0;
  for (auto _ : state) steps = digitize_to_tape(job, p.tape);
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["steps_per_s"] =
      benchmark::Counter(static_cast<double>(steps) * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK(BM_PatternEndToEnd)->Arg(10000)->Arg(100000)->Arg(1000000)->ArgName("vertices")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PatternDigitize)->Arg(10000)->Arg(100000)->ArgName("vertices")->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
