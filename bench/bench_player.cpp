// The player's step compression and the sustained step rate the link reaches at 115200 baud.
//  - BM_Compress/<tape>/<K>: compression speed (steps/s of host CPU) and the schedule's size (bytes per step,
//    steps per run) for a seed example tape at speed scale K on a 1 us controller tick;
//  - BM_CompressShape/<tape>/<K>/<shape>: the same with simpler runs, to show what each part of the run pays:
//    shape 0 quadratic runs anchored at the previous run's end (version 1's runs), 1 quadratic with a free offset,
//    2 cubic anchored, 3 cubic with a free offset (version 2, the default);
//  - BM_Link115200/<tape>/<K>: the whole host link against the emulated controller over an emulated 115200 baud
//    line (virtual clock; framing, acknowledgements, status polling included): machine steps per second of
//    controller time, underruns, and all link bytes per step (frames, retransmissions, polls) with a 128-item
//    controller buffer; 11520 bytes/s divided by that is the sustained rate the line can carry;
//  - BM_PlanSlow/<1/K>/<tick ns>: preparing a million steps (a 62.5-turn spiral, bench/jobs/spiral_1e6.toml) for the
//    controller, plan and schedule, at speed scale 1/K on a controller tick of 1 us or 100 ns: the time must grow
//    with the steps only, not with the ticks between them (steps/s of host CPU, runs, steps the run search
//    proposed per step);
//  - BM_LinkSustained/<tape>/<K>: a long job (the tape played forward and back five times) at a speed scale K where
//    the machine steps 50 000 times a second or more, through the same link with a 128-item controller buffer:
//    the machine's average step rate, underruns (0: the line kept up the whole time), link bytes per step and
//    the fraction of the line's time the host spent sending.
#include <benchmark/benchmark.h>

#include <map>
#include <string>

#include "job/job.hpp"
#include "pipeline/job_tape.hpp"
#include "machine/controller/emulator.hpp"
#include "machine/link/host_link.hpp"
#include "machine/player/play_plan.hpp"
#include "machine/player/schedule.hpp"

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

// The plan of tape range(0) at speed factor range(1).
PlayPlan plan_of(const benchmark::State& st) {
  PlayScaling sc;
  sc.speed = Ratio{st.range(1), 1};
  return plan_playback(tape(static_cast<int>(st.range(0))), sc, std::nullopt);
}

// The schedule's queue items as the link sends them.
std::string encoded(const Schedule& s) {
  std::string bytes;
  ItemCodec c;
  for (const QueueItem& it : s.items) c.encode(it, bytes);
  return bytes;
}

void BM_Compress(benchmark::State& st) {
  const PlayPlan plan = plan_of(st);
  Schedule s;
  for (auto _ : st) {
    s = compress_schedule(plan, 1000000);
    benchmark::DoNotOptimize(s.items.data());
  }
  const std::string bytes = encoded(s);
  const double steps = static_cast<double>(plan.steps.size());
  st.SetLabel(std::string(kTapes[st.range(0)]) + " x" + std::to_string(st.range(1)));
  st.counters["steps/s"] = benchmark::Counter(steps, benchmark::Counter::kIsIterationInvariantRate);
  st.counters["bytes/step"] = static_cast<double>(bytes.size()) / steps;
  st.counters["steps/run"] = steps / static_cast<double>(s.runs);
  // queue bytes a 115200 baud line could carry if it carried nothing else, in steps per second
  st.counters["payload_limit_steps/s"] = 11520.0 / (static_cast<double>(bytes.size()) / steps);
}

void BM_CompressShape(benchmark::State& st) {
  const PlayPlan plan = plan_of(st);
  RunShape shape;
  shape.offset = st.range(2) & 1;
  shape.cubic = st.range(2) & 2;
  Schedule s;
  for (auto _ : st) {
    s = compress_schedule(plan, 1000000, shape);
    benchmark::DoNotOptimize(s.items.data());
  }
  const std::string bytes = encoded(s);
  const double steps = static_cast<double>(plan.steps.size());
  static const char* names[] = {"quadratic anchored", "quadratic + offset", "cubic anchored", "cubic + offset"};
  st.SetLabel(std::string(kTapes[st.range(0)]) + " x" + std::to_string(st.range(1)) + " " + names[st.range(2)]);
  st.counters["bytes/step"] = static_cast<double>(bytes.size()) / steps;
  st.counters["steps/run"] = steps / static_cast<double>(s.runs);
  st.counters["bytes/run"] = static_cast<double>(bytes.size()) / static_cast<double>(s.runs);
}

const std::string& spiral_tape() {
  static const std::string path = [] {
    const std::string p = "/tmp/polarcam-bench-spiral_1e6.tape";
    Job job = load_job(std::string(POLARCAM_SOURCE_DIR) + "/bench/jobs/spiral_1e6.toml");
    TapeHeader h = tape_header_for(job);
    TapeWriter w(p, h);
    DigitizedJob d = digitize_job(job, &w);
    complete_header(h, d.result);
    w.finish(h);
    return p;
  }();
  return path;
}

void BM_PlanSlow(benchmark::State& st) {
  PlayScaling sc;
  sc.speed = Ratio{1, st.range(0)};
  const uint64_t tick_ps = static_cast<uint64_t>(st.range(1)) * 1000;
  const std::string& tape = spiral_tape();
  Schedule s;
  size_t steps = 0;
  for (auto _ : st) {
    const PlayPlan plan = plan_playback(tape, sc, std::nullopt);
    s = compress_schedule(plan, tick_ps);
    steps = plan.steps.size();
    benchmark::DoNotOptimize(s.items.data());
  }
  st.SetLabel("spiral 1e6 steps x1/" + std::to_string(st.range(0)) + " tick " + std::to_string(st.range(1)) + " ns");
  st.counters["steps/s"] = benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsIterationInvariantRate);
  st.counters["runs"] = static_cast<double>(s.runs);
  st.counters["searched/step"] = static_cast<double>(s.searched_steps) / static_cast<double>(steps);
}

void BM_Link115200(benchmark::State& st) {
  const PlayPlan plan = plan_of(st);
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

// The plan played forward, then backward (each step undone in reverse order, mirrored in time), `cycles` times.
PlayPlan back_and_forth(const PlayPlan& p, int cycles) {
  PlayPlan out = p;
  out.steps.clear();
  const uint64_t T = p.steps.back().t, gap = T / p.steps.size() + 1;
  for (int c = 0; c < cycles; ++c) {
    const uint64_t t0 = static_cast<uint64_t>(c) * (2 * T + 2 * gap);
    for (const PlayStep& s : p.steps) {
      PlayStep f = s;
      f.t += t0;
      out.steps.push_back(f);
    }
    for (size_t i = p.steps.size(); i-- > 0;) {
      PlayStep b = p.steps[i];
      b.t = t0 + 2 * T + gap - p.steps[i].t;
      b.dir = static_cast<int8_t>(-b.dir);
      out.steps.push_back(b);
    }
  }
  out.end[0] = p.start[0];
  out.end[1] = p.start[1];
  out.steps_per_axis[0] = p.steps_per_axis[0] * 2 * static_cast<uint64_t>(cycles);
  out.steps_per_axis[1] = p.steps_per_axis[1] * 2 * static_cast<uint64_t>(cycles);
  return out;
}

void BM_LinkSustained(benchmark::State& st) {
  PlayScaling sc;
  sc.speed = Ratio{st.range(1), 1};
  const PlayPlan plan = back_and_forth(plan_playback(tape(static_cast<int>(st.range(0))), sc, std::nullopt), 5);
  PlayReport rep;
  for (auto _ : st) {
    ControllerSpec spec;
    spec.slots = 128;
    SimTransport tr(spec, 115200, FaultSpec{});
    HostLink link(tr, LinkOptions{});
    proto::Ident id = link.identify();
    Schedule s = compress_schedule(plan, id.tick_ps);
    rep = link.play(plan, s);
  }
  st.SetLabel(std::string(kTapes[st.range(0)]) + " x" + std::to_string(st.range(1)) + " forward and back x5");
  st.counters["steps"] = static_cast<double>(rep.steps_confirmed);
  st.counters["machine_steps/s"] = static_cast<double>(rep.steps_confirmed) / rep.duration_s;
  st.counters["underruns"] = static_cast<double>(rep.underruns);
  const double bps = static_cast<double>(rep.bytes_sent) / static_cast<double>(rep.steps_confirmed);
  st.counters["link_bytes/step"] = bps;
  st.counters["sustainable_steps/s"] = 11520.0 / bps;
  st.counters["line_busy"] = static_cast<double>(rep.bytes_sent) * 10.0 / 115200.0 / rep.wall_s;
}

}  // namespace

BENCHMARK(BM_Compress)->ArgsProduct({{0, 1, 2, 3}, {1, 10, 50}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CompressShape)->ArgsProduct({{0, 1, 2, 3}, {1, 50}, {0, 1, 2, 3}})->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_PlanSlow)->ArgsProduct({{1, 15, 150}, {1000, 100}})->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Link115200)->ArgsProduct({{0, 1, 2, 3}, {1, 10, 50, 100, 200}})->Unit(benchmark::kMillisecond)->Iterations(1);
// speed scales at which each tape's machine averages 50 000 steps/s or more (limacon 627, witch 231, serpentine
// 956, circle 503 steps/s at 1x)
BENCHMARK(BM_LinkSustained)->Args({0, 100})->Args({1, 250})->Args({2, 60})->Args({3, 100})->Args({0, 200})
    ->Args({1, 500})->Args({2, 120})->Args({3, 200})->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_MAIN();
