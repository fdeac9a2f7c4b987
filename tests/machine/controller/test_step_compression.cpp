// The step schedule of protocol version 2: the run arithmetic against its closed form, the validity rule against
// brute force, the wire codec (round trip, damaged bytes), and the compressor on analytic and noisy step
// sequences, every executed step checked against its exact time independently.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "cam/error.hpp"
#include "machine/controller/controller.hpp"
#include "machine/player/int128.hpp"
#include "machine/player/play_plan.hpp"
#include "machine/link/protocol.hpp"
#include "machine/player/schedule.hpp"
#include "machine/controller/sim_machine.hpp"
#include "tests/player_helpers.hpp"

namespace polarcam {
namespace tu_machine_controller_test_step_compression {  // named: the test files compile together

constexpr int64_t kTick = int64_t{1} << 32;

i128 binom(i128 k, int j) {
  i128 r = 1;
  for (int i = 0; i < j; ++i) r = r * (k - i) / (i + 1);
  return r;
}

QueueItem run(uint32_t n, int64_t off, int64_t I, int64_t A, int64_t B, int axis = 0, int dir = 1) {
  QueueItem it;
  it.kind = ItemKind::run;
  it.axis = static_cast<uint8_t>(axis);
  it.dir = static_cast<int8_t>(dir);
  it.count = n;
  it.offset = off;
  it.interval = I;
  it.add = A;
  it.add2 = B;
  return it;
}

// Every interval and add of a run, one by one (no closed forms): the definition the validity rule must match.
bool brute_force_valid(const QueueItem& r) {
  if (r.count == 0 || r.count > kMaxRunCount) return false;
  const i128 lim = static_cast<i128>(1) << 62;
  i128 iv = r.interval, add = r.add;
  for (uint32_t k = 1; k <= r.count; ++k) {
    const i128 step = k == 1 ? r.offset + iv : iv;
    if (step < kOneTick || step > kMaxIntervalFx) return false;
    if (add < -lim || add > lim) return false;
    if (k < r.count) {
      iv += add;
      add += r.add2;
    }
  }
  if (r.add2 < -lim || r.add2 > lim || add < -lim || add > lim) return false;
  return true;
}

TEST(StepCompression, RunCursorFollowsTheCubicClosedForm) {
  std::mt19937_64 rng(5);
  int checked = 0;
  while (checked < 200) {
    const uint32_t n = 1 + static_cast<uint32_t>(rng() % 3000);
    const int64_t I = kTick + static_cast<int64_t>(rng() % (2000 * static_cast<uint64_t>(kTick)));
    const int64_t A = static_cast<int64_t>(rng() % (1u << 30)) - (1 << 29);
    const int64_t B = static_cast<int64_t>(rng() % (1u << 16)) - (1 << 15);
    const int64_t off = static_cast<int64_t>(rng() % (4 * static_cast<uint64_t>(kTick))) - 2 * kTick;
    QueueItem it = run(n, off, I, A, B);
    if (!run_is_valid(it)) continue;
    RunCursor c;
    c.begin(it);
    i128 pos = 0;
    for (uint32_t k = 1; k <= n; ++k) {
      pos += c.next();
      ASSERT_EQ(pos, off + k * static_cast<i128>(I) + binom(k, 2) * A + binom(k, 3) * B) << "step " << k;
    }
    EXPECT_EQ(c.left, 0u);
    // the wire's prediction is the run continued by one step
    const RunRef ref = continuation(it);
    const int64_t next_iv = ref.interval;
    EXPECT_EQ(static_cast<i128>(next_iv), off + (n + 1) * static_cast<i128>(I) + binom(n + 1, 2) * A + binom(n + 1, 3) * B - pos);
    ++checked;
  }
}

TEST(StepCompression, RunValidityMatchesBruteForce) {
  std::mt19937_64 rng(7);
  int valid = 0, invalid = 0;
  for (int i = 0; i < 20000; ++i) {
    const uint32_t n = static_cast<uint32_t>(rng() % 40);  // includes 0
    // intervals near one tick, adds that turn them around inside the run, offsets that spoil the first step
    const int64_t I = kTick + static_cast<int64_t>(rng() % (40 * static_cast<uint64_t>(kTick))) - 4 * kTick;
    const int64_t A = static_cast<int64_t>(rng() % (8 * static_cast<uint64_t>(kTick))) - 4 * kTick;
    const int64_t B = static_cast<int64_t>(rng() % (static_cast<uint64_t>(kTick) / 2)) - kTick / 4;
    const int64_t off = rng() % 3 == 0 ? 0 : static_cast<int64_t>(rng() % (8 * static_cast<uint64_t>(kTick))) - 4 * kTick;
    const QueueItem it = run(n, off, I, A, B);
    const bool v = run_is_valid(it);
    ASSERT_EQ(v, brute_force_valid(it)) << "n " << n << " off " << off << " I " << I << " A " << A << " B " << B;
    (v ? valid : invalid)++;
  }
  EXPECT_GT(valid, 1000);
  EXPECT_GT(invalid, 1000);
  // the parabola of intervals dips below one tick only in the middle of the run: both ends are fine
  QueueItem dip = run(21, 0, 11 * kTick, -2 * kTick, kTick / 5);
  EXPECT_GE(dip.interval + 20 * dip.add + 190 * dip.add2, kTick);
  EXPECT_FALSE(run_is_valid(dip));
  EXPECT_FALSE(run_is_valid(run(10, -kTick, kTick / 2 + kTick, 0, 0)));  // first interval: half a tick
  EXPECT_TRUE(run_is_valid(run(10, -kTick / 2, kTick + kTick / 2, 0, 0)));
  EXPECT_FALSE(run_is_valid(run(kMaxRunCount + 1, 0, kTick, 0, 0)));
  EXPECT_FALSE(run_is_valid(run(3, 0, kTick, int64_t{1} << 62, -(int64_t{1} << 62))));  // intervals beyond 2^30 ticks
}

std::vector<QueueItem> random_items(std::mt19937_64& rng, size_t count) {
  std::vector<QueueItem> v;
  while (v.size() < count) {
    const int axis = static_cast<int>(rng() % 2), pick = static_cast<int>(rng() % 10);
    if (pick == 0) {
      QueueItem w;
      w.kind = ItemKind::wait;
      w.axis = static_cast<uint8_t>(axis);
      w.wait = rng() >> (rng() % 64);
      v.push_back(w);
      continue;
    }
    // from tiny to extreme values, some equal to round numbers
    auto val = [&](int bits) {
      const int64_t x = static_cast<int64_t>(rng() >> (64 - bits)) - (int64_t{1} << (bits - 1));
      return rng() % 4 == 0 ? x & ~int64_t{0xffff} : x;
    };
    QueueItem r = run(1 + static_cast<uint32_t>(rng() % kMaxRunCount), val(34), 0, val(20), val(8), axis,
                      rng() % 2 ? 1 : -1);
    r.interval = kTick + static_cast<int64_t>(rng() >> (2 + rng() % 60));
    if (rng() % 8 == 0) r = run(1 + static_cast<uint32_t>(rng() % 4), 0, (int64_t{1} << 62) - kTick, 0, 0, axis, 1);
    if (run_is_valid(r)) v.push_back(r);
  }
  return v;
}

TEST(StepCompression, CodecRoundTripsRandomItems) {
  std::mt19937_64 rng(11);
  const std::vector<QueueItem> items = random_items(rng, 3000);
  test::expect_codec_round_trip(items);
}

TEST(StepCompression, DamagedItemsAreRejectedNeverMisread) {
  // a run whose intervals dip below one tick in the middle cannot be sent: the decoder refuses it
  {
    ItemCodec enc, dec;
    std::string b;
    enc.encode(run(21, 0, 11 * kTick, -2 * kTick, kTick / 5), b);
    size_t pos = 0;
    QueueItem x;
    EXPECT_FALSE(dec.decode(reinterpret_cast<const uint8_t*>(b.data()), b.size(), pos, x));
    EXPECT_EQ(pos, 0u);
  }
  std::mt19937_64 rng(13);
  std::vector<QueueItem> items = random_items(rng, 40);
  ItemCodec enc;
  std::string bytes;
  for (const QueueItem& it : items) enc.encode(it, bytes);
  // every truncation of the last item fails; every bit flip decodes to valid items or fails, never to an
  // invalid run, and the decoder's state is untouched by a failed item
  std::string last;
  {
    ItemCodec e2;
    std::string prefix;
    for (size_t i = 0; i + 1 < items.size(); ++i) e2.encode(items[i], prefix);
    e2.encode(items.back(), last);
    ASSERT_EQ(prefix + last, bytes);
  }
  for (size_t cut = bytes.size() - last.size(); cut < bytes.size(); ++cut) {
    ItemCodec dec;
    size_t pos = 0;
    QueueItem x;
    size_t n = 0;
    while (dec.decode(reinterpret_cast<const uint8_t*>(bytes.data()), cut, pos, x)) ++n;
    EXPECT_EQ(n, items.size() - 1) << "cut at " << cut;
  }
  for (size_t i = 0; i < bytes.size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      std::string b = bytes;
      b[i] = static_cast<char>(b[i] ^ (1 << bit));
      ItemCodec dec;
      size_t pos = 0;
      QueueItem x;
      while (pos < b.size()) {
        const ItemCodec before = dec;
        const size_t p0 = pos;
        if (!dec.decode(reinterpret_cast<const uint8_t*>(b.data()), b.size(), pos, x)) {
          EXPECT_EQ(pos, p0);
          EXPECT_EQ(dec.ref[0].interval, before.ref[0].interval);
          EXPECT_EQ(dec.ref[1].add, before.ref[1].add);
          break;
        }
        ASSERT_TRUE(run_is_valid(x)) << "byte " << i << " bit " << bit;
      }
    }
}

// ---- the compressor on synthetic step sequences --------------------------------------------------------

struct Synth {
  int axis, dir;
  uint64_t t_ns;
};

PlayPlan synthetic_plan(const std::vector<Synth>& steps) {
  PlayPlan p;
  p.tape = "synthetic";
  p.header.tick_ps = 1000;  // tape ticks of 1 ns
  for (size_t i = 0; i < steps.size(); ++i) {
    PlayStep s;
    s.t = steps[i].t_ns;
    s.record = i + 1;
    s.axis = static_cast<uint8_t>(steps[i].axis);
    s.dir = static_cast<int8_t>(steps[i].dir);
    p.steps.push_back(s);
    ++p.steps_per_axis[s.axis];
    (s.axis == 0 ? p.end[0] : p.end[1]) += s.dir;
  }
  return p;
}

// Executes the schedule with the controller's arithmetic and checks, independently of the compressor, that every
// step is within one tick of its exact time (1 ns tape ticks, speed 1), that each axis steps at most once a tick
// and that steps of different axes keep the plan's order (the radial axis first within a tick).
void expect_exact(const PlayPlan& p, const Schedule& sc) {
  std::vector<uint64_t> ticks[2] = {execute_axis(sc.items, 0), execute_axis(sc.items, 1)};
  size_t k[2] = {0, 0};
  std::vector<uint64_t> e(p.steps.size());
  for (size_t i = 0; i < p.steps.size(); ++i) {
    const int a = p.steps[i].axis;
    ASSERT_LT(k[a], ticks[a].size());
    e[i] = ticks[a][k[a]++];
    const i128 d = static_cast<i128>(e[i]) * static_cast<i128>(sc.tick_ps) - static_cast<i128>(p.steps[i].t) * 1000;
    ASSERT_LE(d < 0 ? -d : d, static_cast<i128>(sc.tick_ps)) << "step " << i + 1;
  }
  EXPECT_EQ(k[0], ticks[0].size());
  EXPECT_EQ(k[1], ticks[1].size());
  uint64_t last[2] = {0, 0};
  bool any[2] = {false, false};
  for (size_t i = 0; i < e.size(); ++i) {
    const int a = p.steps[i].axis;
    if (any[a]) {
      ASSERT_GT(e[i], last[a]) << "step " << i + 1;
    }
    any[a] = true;
    last[a] = e[i];
    if (i + 1 < e.size() && p.steps[i + 1].axis != a) {
      if (a == 0) {
        ASSERT_LE(e[i], e[i + 1]) << "step " << i + 1;
      } else {
        ASSERT_LT(e[i], e[i + 1]) << "step " << i + 1;
      }
    }
  }
}

TEST(StepCompression, ConstantRateRunsAreAsLongAsTheWireAllows) {
  std::vector<Synth> s;
  for (uint64_t k = 1; k <= 140000; ++k) s.push_back({1, -1, 150 + 3700 * k});  // 3.7 us apart
  const PlayPlan p = synthetic_plan(s);
  const Schedule sc = compress_schedule(p, 1000000);
  expect_exact(p, sc);
  EXPECT_EQ(sc.runs, (140000 + kMaxRunCount - 1) / kMaxRunCount);
}

TEST(StepCompression, ACubicTimeLawIsOneRunPerDirection) {
  // t(k) = 1 ms + 150 us k + 20 ns k^2 + 0.01 ns k^3 on the radial axis, out and back; the angular axis steps
  // at a constant rate in between; nothing but the direction change and the axis ends a run
  std::vector<Synth> s;
  auto law = [](double k) { return 1e6 + 150e3 * k + 20 * k * k + 0.01 * k * k * k; };
  for (int k = 1; k <= 3000; ++k) s.push_back({0, k <= 1500 ? 1 : -1, static_cast<uint64_t>(std::llround(law(k)))});
  for (int k = 1; k <= 2000; ++k) s.push_back({1, 1, 800000 + static_cast<uint64_t>(k) * 333333});
  std::stable_sort(s.begin(), s.end(), [](const Synth& a, const Synth& b) { return a.t_ns < b.t_ns; });
  const PlayPlan p = synthetic_plan(s);
  const Schedule sc = compress_schedule(p, 1000000);
  expect_exact(p, sc);
  EXPECT_EQ(sc.runs, 3u);
}

TEST(StepCompression, NoisyStepsStayWithinOneTickAndInOrder) {
  // random intervals from 1.2 us to 60 us on both axes, with many cross-axis pairs inside one tick: the runs are
  // short and the split windows and the single-step fallback are exercised
  std::mt19937_64 rng(17);
  std::vector<Synth> s;
  uint64_t t[2] = {0, 0};
  for (int i = 0; i < 6000; ++i) {
    const int a = static_cast<int>(rng() % 2);
    t[a] += 1200 + rng() % (rng() % 3 == 0 ? 60000 : 4000);
    s.push_back({a, rng() % 50 == 0 ? -1 : 1, t[a]});
  }
  std::stable_sort(s.begin(), s.end(), [](const Synth& a, const Synth& b) { return a.t_ns < b.t_ns; });
  const PlayPlan p = synthetic_plan(s);
  const Schedule sc = compress_schedule(p, 1000000);
  expect_exact(p, sc);
  // and the controller executes the same steps in the plan's order
  SimResult r = simulate_playback(p, sc, PlayMachine{});
  EXPECT_EQ(r.mismatched, 0u);
  EXPECT_EQ(r.steps, p.steps.size());
  EXPECT_LE(r.max_time_error_ns, 1000.0);
}

TEST(StepCompression, CloseStepsOfTwoAxesSplitTheirWindows) {
  // radial at 10.2 us then angular at 10.9 us (may share a tick: the radial axis steps first); angular at 30.2 us
  // then radial at 30.7 us (must not share one)
  const PlayPlan p = synthetic_plan({{0, 1, 10200}, {1, 1, 10900}, {1, 1, 30200}, {0, 1, 30700}});
  const std::vector<StepWindow> w = step_windows(p, 1000000);
  // within one tick of the exact times: [10, 11], [10, 11], [30, 31], [30, 31]; split at the rounded midpoint
  // (10.55 -> 11, both steps may take tick 11; (30.2 + 30.7 - 1) / 2 = 29.95 -> 30, the radial step after it)
  EXPECT_EQ(w[0].lo, 10);
  EXPECT_EQ(w[0].hi, 11);  // keeps two ticks (pinning kept one)
  EXPECT_EQ(w[1].lo, 11);
  EXPECT_EQ(w[1].hi, 11);
  EXPECT_EQ(w[2].lo, 30);
  EXPECT_EQ(w[2].hi, 30);
  EXPECT_EQ(w[3].lo, 31);
  EXPECT_EQ(w[3].hi, 31);
  expect_exact(p, compress_schedule(p, 1000000));
}

TEST(StepCompression, NothingStepsAtTheStartTick) {
  // radial at 0.2 us, angular at 0.5 us: both must wait for tick 1 (a run's first interval is at least a tick),
  // where the radial axis steps first; the other order cannot be kept within one tick
  const PlayPlan p = synthetic_plan({{0, 1, 200}, {1, 1, 500}, {0, 1, 5000}, {1, 1, 7000}});
  const std::vector<StepWindow> w = step_windows(p, 1000000);
  EXPECT_EQ(w[0].lo, 1);
  EXPECT_EQ(w[0].hi, 1);
  EXPECT_EQ(w[1].lo, 1);
  expect_exact(p, compress_schedule(p, 1000000));
  EXPECT_THROW(compress_schedule(synthetic_plan({{1, 1, 200}, {0, 1, 500}}), 1000000), InputError);
}

TEST(StepCompression, StepsOfOneAxisWithinOneTickAreRefused) {
  const PlayPlan p = synthetic_plan({{0, 1, 10000}, {0, 1, 10300}, {0, 1, 10600}, {0, 1, 10900}});
  try {
    compress_schedule(p, 1000000);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("machine step 4 (radial, from tape record 4) comes less than one controller tick"),
              std::string::npos)
        << e.what();
  }
}

TEST(StepCompression, ControllerFaultsOnAnInvalidRunAndIgnoresDamagedFrames) {
  ControllerSpec spec;
  Controller c(spec);
  proto::Configure cfg;
  cfg.tick_ps = spec.tick_ps;
  ASSERT_TRUE(c.configure(cfg, nullptr));
  c.take_output();
  // a damaged frame (CRC) is dropped: nothing queued, the controller asks for nothing and stays ready
  ItemCodec enc;
  std::string good;
  enc.encode(run(5, 0, 10 * kTick, kTick, 0), good);
  std::string f = proto::encode_frame(1, proto::QUEUE, good);
  f[8] = static_cast<char>(f[8] ^ 0x04);
  c.receive(reinterpret_cast<const uint8_t*>(f.data()), f.size(), 0);
  EXPECT_EQ(c.status().queued, 0u);
  EXPECT_EQ(c.status().bad_frames, 1u);
  EXPECT_EQ(c.state(), proto::State::ready);
  // an intact frame carrying a run that steps faster than the tick: refused, reported, nothing queued
  ItemCodec enc2;
  std::string bad;
  enc2.encode(run(21, 0, 11 * kTick, -2 * kTick, kTick / 5), bad);
  const std::string g = proto::encode_frame(1, proto::QUEUE, bad);
  c.receive(reinterpret_cast<const uint8_t*>(g.data()), g.size(), 0);
  EXPECT_EQ(c.state(), proto::State::fault);
  EXPECT_EQ(c.status().error, proto::ErrorCode::bad_queue);
  EXPECT_EQ(c.status().queued, 0u);
  std::vector<proto::Frame> out;
  proto::FrameDecoder d;
  const std::string o = c.take_output();
  d.feed(reinterpret_cast<const uint8_t*>(o.data()), o.size(), out);
  ASSERT_FALSE(out.empty());
  EXPECT_EQ(out.front().type, proto::ERROR);
  // and an invalid run cannot be pushed in-process either
  EXPECT_FALSE(c.push(run(21, 0, 11 * kTick, -2 * kTick, kTick / 5)));
}

// The angular steps of a 10-turn Archimedean spiral from r = 5 mm (pitch 0.3 mm, 16000 steps a turn) at a
// constant speed v: t(theta) = s(theta) / v with the spiral's arc length in closed form,
// s = (r sqrt(r^2 + b^2) + b^2 asinh(r / b)) / (2b), r = a + b theta.
std::vector<Synth> spiral_steps(long double v, uint64_t n) {
  const long double pi = 3.14159265358979323846L;
  const long double a = 5e-3L, b = 0.3e-3L / (2 * pi), dth = 2 * pi / 16000;
  auto arc = [&](long double th) {
    const long double r = a + b * th;
    return (r * std::sqrt(r * r + b * b) + b * b * std::asinh(r / b)) / (2 * b);
  };
  std::vector<Synth> s;
  for (uint64_t k = 1; k <= n; ++k)
    s.push_back({1, 1, static_cast<uint64_t>(std::llround((arc(dth * static_cast<long double>(k)) - arc(0)) / v * 1e9L))});
  return s;
}

TEST(StepCompression, SlowStepsCostTheSameSearchAsFastOnes) {
  // At 1.52 cm/s the steps are 0.13 ms apart; at 1 mm/s 2 ms and at 0.1 mm/s 20 ms. The wire's rounding of a
  // long run's parameters spoils the slow runs; the compressor once kept one step of each spoiled run and searched
  // the whole stretch again (runs as many as the steps, minutes of work). The same steps must cost the same
  // search, a few times the steps, and stay a few runs, whatever the time between them.
  const uint64_t n = 160000;
  for (long double v : {1.52e-2L, 1e-3L, 1e-4L}) {
    const PlayPlan p = synthetic_plan(spiral_steps(v, n));
    const Schedule sc = compress_schedule(p, 1000000);
    expect_exact(p, sc);
    EXPECT_LE(sc.runs, 16u) << "v = " << static_cast<double>(v);
    EXPECT_LE(sc.searched_steps, 4 * n) << "v = " << static_cast<double>(v);
    EXPECT_GE(sc.searched_steps, n);  // every step was searched at least once
  }
}

}  // namespace tu_machine_controller_test_step_compression
}  // namespace polarcam
