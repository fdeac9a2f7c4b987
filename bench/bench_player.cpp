// The player's step compression and the sustained step rate the link reaches at 115200 baud.
//  - BM_Compress/<tape>/<K>: compression speed (steps/s of host CPU) and the schedule's size (bytes per step,
//    steps per run) for a seed example tape at speed scale K on a 1 us controller tick;
//  - BM_Link115200/<tape>/<K>: the whole host link against the emulated controller over an emulated 115200 baud
//    line (virtual clock; framing, acknowledgements, status polling included): machine steps per second of
//    controller time, underruns, and all link bytes per step (frames, retransmissions, polls) with a 128-item
//    controller buffer; 11520 bytes/s divided by that is the sustained rate the line can carry.
#include <benchmark/benchmark.h>

#include <map>
#include <string>

#include "app/job.hpp"
#include "app/job_tape.hpp"
#include "machine/emulator.hpp"
#include "machine/host_link.hpp"
#include "machine/play_plan.hpp"
#include "machine/schedule.hpp"

namespace {

using namespace polarcam;

const char* kTapes[] = {"limacon", "witch", "serpentine", "circle"};

const std::string& tape(int i) {
  static std::map<int, std::string> made;
  auto it = made.find(i);
  if (it != made.end()) return it->second;
  const std::string path = "/tmp/polarcam-bench-" + std::string(kTapes[i]) + ".tape";
  Job job = load_job(std::string(POLARCAM_SOURCE_DIR) + "/examples/" + kTapes[i] + ".toml");
  TapeHeader h = tape_header_for(job);
  TapeWriter w(path, h);
  DigitizedJob d = digitize_job(job, &w);
  complete_header(h, d.result);
  w.finish(h);
  return made[i] = path;
}

void BM_Compress(benchmark::State& st) {
  PlayScaling sc;
  sc.speed = Ratio{st.range(1), 1};
  PlayPlan plan = plan_playback(tape(static_cast<int>(st.range(0))), sc, std::nullopt);
  Schedule s;
  for (auto _ : st) {
    s = compress_schedule(plan, 1000000);
    benchmark::DoNotOptimize(s.items.data());
  }
  std::string bytes;
  ItemCodec c;
  for (const QueueItem& it : s.items) c.encode(it, bytes);
  const double steps = static_cast<double>(plan.steps.size());
  st.SetLabel(std::string(kTapes[st.range(0)]) + " x" + std::to_string(st.range(1)));
  st.counters["steps/s"] = benchmark::Counter(steps, benchmark::Counter::kIsIterationInvariantRate);
  st.counters["bytes/step"] = static_cast<double>(bytes.size()) / steps;
  st.counters["steps/run"] = steps / static_cast<double>(s.runs);
  // queue bytes a 115200 baud line could carry if it carried nothing else, in steps per second
  st.counters["payload_limit_steps/s"] = 11520.0 / (static_cast<double>(bytes.size()) / steps);
}

void BM_Link115200(benchmark::State& st) {
  PlayScaling sc;
  sc.speed = Ratio{st.range(1), 1};
  PlayPlan plan = plan_playback(tape(static_cast<int>(st.range(0))), sc, std::nullopt);
  PlayReport rep;
  for (auto _ : st) {
    ControllerSpec spec;
    spec.slots = 128;  // a small buffer: the link must keep up while the job runs, not before START
    SimTransport tr(spec, 115200, FaultSpec{});
    HostLink link(tr, LinkOptions{});
    proto::Ident id = link.identify();
    Schedule s = compress_schedule(plan, id.tick_ps);
    rep = link.play(plan, s);
  }
  st.SetLabel(std::string(kTapes[st.range(0)]) + " x" + std::to_string(st.range(1)));
  st.counters["machine_steps/s"] = static_cast<double>(rep.steps_confirmed) / rep.duration_s;
  st.counters["underruns"] = static_cast<double>(rep.underruns);
  const double bps = static_cast<double>(rep.bytes_sent) / static_cast<double>(rep.steps_confirmed);
  st.counters["link_bytes/step"] = bps;
  st.counters["sustainable_steps/s"] = 11520.0 / bps;  // the line's 11520 bytes/s over all bytes sent per step
}

}  // namespace

BENCHMARK(BM_Compress)->ArgsProduct({{0, 1, 2, 3}, {1, 10, 50}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Link115200)->ArgsProduct({{0, 1, 2, 3}, {1, 10, 50, 100, 200}})->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_MAIN();
