// The player: speed and size scaling, the angular offset, the work area, and the exactness of the compressed
// schedule against the tape read independently.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "cam/error.hpp"
#include "machine/player/play_plan.hpp"
#include "machine/player/scaling.hpp"
#include "machine/player/schedule.hpp"
#include "tests/player_helpers.hpp"

namespace polarcam {
namespace tu_machine_player_test_player {  // named: the test files compile together

using test::example_tape;
using test::read_tape;
using test::scaling;

TEST(Scaling, ParsesExactRatios) {
  Ratio r = parse_ratio("2", "x");
  EXPECT_EQ(r.num, 2);
  EXPECT_EQ(r.den, 1);
  r = parse_ratio("0.25", "x");
  EXPECT_EQ(r.num, 1);
  EXPECT_EQ(r.den, 4);
  r = parse_ratio("6/4", "x");
  EXPECT_EQ(r.num, 3);
  EXPECT_EQ(r.den, 2);
  r = parse_ratio("1.5/0.5", "x");
  EXPECT_EQ(r.num, 3);
  EXPECT_EQ(r.den, 1);
  for (const char* bad : {"0", "-1", "abc", "1/0", "", "1/", "2.3.4", "1e3", "0/5"})
    EXPECT_THROW(parse_ratio(bad, "--speed-scale"), InputError) << bad;
  try {
    parse_ratio("fast", "--speed-scale");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--speed-scale"), std::string::npos);
  }
  auto why = [](const std::string& text) {
    try {
      parse_ratio(text, "--speed-scale");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(why("3/0").find("zero denominator"), std::string::npos) << why("3/0");
  // 31-bit parts: 2^31 - 1 fits, 2^31 does not
  EXPECT_EQ(parse_ratio("2147483647", "x").num, 2147483647);
  EXPECT_NE(why("2147483648").find("must fit 31 bits"), std::string::npos) << why("2147483648");
  EXPECT_NE(why("1/2147483648").find("must fit 31 bits"), std::string::npos);
}

TEST(Scaling, RadialIndexIsTheNearestToNTimesPOverQHalvesUp) {
  for (auto [p, q] : {std::pair<int64_t, int64_t>{1, 2}, {2, 1}, {3, 4}, {7, 3}, {1, 1}, {5, 8}})
    for (int64_t n = -50; n <= 20000; n += (n < 100 ? 1 : 97)) {
      // independent: exact rational rounding, n p / q = k + f
      const int64_t num = n * p;
      int64_t k = num / q, rem = num % q;
      if (rem < 0) {
        --k;
        rem += q;
      }
      const int64_t expect = 2 * rem >= q ? k + 1 : k;
      EXPECT_EQ(scaled_radial_index(n, Ratio{p, q}), expect) << n << " " << p << "/" << q;
    }
  EXPECT_EQ(scaled_radial_index(4501, Ratio{1, 2}), 2251);  // 2250.5 rounds up
  EXPECT_EQ(scaled_radial_index(4499, Ratio{1, 2}), 2250);  // 2249.5 rounds up
  // 2^62 scaled 2/1 is 2^63, beyond int64: refused, not wrapped
  EXPECT_THROW(scaled_radial_index(int64_t{1} << 62, Ratio{2, 1}), InputError);
  EXPECT_THROW(scaled_radial_index(-(int64_t{1} << 62), Ratio{3, 1}), InputError);
  EXPECT_EQ(scaled_radial_index(int64_t{1} << 61, Ratio{2, 1}), int64_t{1} << 62);
}

// Machine node after all machine steps that come from tape records 1..i, for every i.
std::vector<std::pair<int64_t, int64_t>> nodes_by_record(const PlayPlan& p, size_t records) {
  std::vector<int64_t> dn(records + 1, 0), dm(records + 1, 0);
  for (const PlayStep& s : p.steps) (s.axis == 0 ? dn : dm)[s.record] += s.dir;
  std::vector<std::pair<int64_t, int64_t>> out(records + 1);
  int64_t n = p.start[0], m = p.start[1];
  out[0] = {n, m};
  for (size_t i = 1; i <= records; ++i) {
    n += dn[i];
    m += dm[i];
    out[i] = {n, m};
  }
  return out;
}

TEST(Player, SizeScaleTwoDoublesEveryRadialIndexAndKeepsAngularOnes) {
  const std::string tape = example_tape("limacon");
  const auto ref = read_tape(tape);
  PlayPlan p = plan_playback(tape, scaling("1", "2/1"), std::nullopt);
  TapeReader rd(tape);
  EXPECT_EQ(p.start[0], 2 * rd.header().start[0]);
  EXPECT_EQ(p.start[1], rd.header().start[1]);
  auto nodes = nodes_by_record(p, ref.size());
  for (size_t i = 0; i < ref.size(); ++i) {
    ASSERT_EQ(nodes[i + 1].first, 2 * ref[i].n) << "record " << i + 1;
    ASSERT_EQ(nodes[i + 1].second, ref[i].m) << "record " << i + 1;
  }
  // every machine step is in time order, and each radial tape step became two machine steps
  for (size_t i = 1; i < p.steps.size(); ++i) ASSERT_LE(p.steps[i - 1].t, p.steps[i].t);
  EXPECT_EQ(p.steps_per_axis[0], 2 * (rd.header().plus[0] + rd.header().minus[0]));
  EXPECT_EQ(p.steps_per_axis[1], rd.header().plus[1] + rd.header().minus[1]);
}

TEST(Player, SizeScaleHalfHalvesRadialIndexesRoundingHalvesUp) {
  const std::string tape = example_tape("limacon");
  const auto ref = read_tape(tape);
  PlayPlan p = plan_playback(tape, scaling("1", "1/2"), std::nullopt);
  auto nodes = nodes_by_record(p, ref.size());
  for (size_t i = 0; i < ref.size(); ++i) {
    ASSERT_EQ(nodes[i + 1].first, static_cast<int64_t>(std::floor(static_cast<double>(ref[i].n) / 2.0 + 0.5)));
    ASSERT_EQ(nodes[i + 1].second, ref[i].m);
  }
  // a radial machine step happens exactly when the tape's step crosses an odd index upward (n: 2k -> 2k+1
  // rounds up), so it carries the tape step's time
  for (const PlayStep& s : p.steps) ASSERT_EQ(s.t, ref[s.record - 1].t);
}

TEST(Player, AngleOffsetShiftsEveryAngularIndex) {
  const std::string tape = example_tape("witch");
  const auto ref = read_tape(tape);
  PlayPlan p = plan_playback(tape, scaling("1", "1", 100), std::nullopt);
  auto nodes = nodes_by_record(p, ref.size());
  for (size_t i = 0; i < ref.size(); ++i) {
    ASSERT_EQ(nodes[i + 1].first, ref[i].n);
    ASSERT_EQ(nodes[i + 1].second, ref[i].m + 100);
  }
}

TEST(Player, ScalesThatLeaveTheWorkAreaAreRefusedBeforeAnything) {
  const std::string circle = example_tape("circle");  // r from 152 to 254 mm on a 76-330 mm annulus
  try {
    plan_playback(circle, scaling("1", "2"), std::nullopt);
    FAIL() << "size scale 2 takes the circle beyond r_max";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("r_max"), std::string::npos) << e.what();
  }
  EXPECT_THROW(plan_playback(circle, scaling("1", "1/4"), std::nullopt), InputError);  // below r_min
  EXPECT_THROW(plan_playback(circle, scaling("1", "1", 8000), std::nullopt), InputError);  // beyond theta_max
  EXPECT_NO_THROW(plan_playback(circle, scaling("1", "5/4"), std::nullopt));
}

TEST(Player, TapeFromAnotherGridIsRefused) {
  const std::string tape = example_tape("witch");
  PlayMachine m = machine_from_header(TapeReader(tape).header());
  m.source = "machine file other.toml";
  m.grid.dr *= 2;
  try {
    plan_playback(tape, scaling("1"), m);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("another machine grid"), std::string::npos) << e.what();
  }
}

TEST(Schedule, SpeedScaleTwoHalvesEveryInterval) {
  const std::string tape = example_tape("serpentine");
  const auto ref = read_tape(tape);
  PlayPlan p = plan_playback(tape, scaling("2"), std::nullopt);
  Schedule sc = compress_schedule(p, 1000);  // 1 ns tick: the scaled times are t / 2 within 1 ns
  std::vector<uint64_t> ticks[2] = {execute_axis(sc.items, 0), execute_axis(sc.items, 1)};
  size_t k[2] = {0, 0};
  for (size_t i = 0; i < ref.size(); ++i) {
    const uint64_t t = ticks[ref[i].axis][k[ref[i].axis]++];
    ASSERT_LE(std::llabs(static_cast<long long>(2 * t) - static_cast<long long>(ref[i].t)), 2) << i;
  }
}

TEST(Schedule, StepsTooCloseForTheTickAreRefused) {
  const std::string tape = example_tape("limacon");
  PlayPlan p = plan_playback(tape, scaling("100000"), std::nullopt);
  EXPECT_THROW(compress_schedule(p, 1000000), InputError);
}

TEST(Schedule, ItemCodecRoundTripsAndRejectsGarbage) {
  const std::string tape = example_tape("witch");
  PlayPlan p = plan_playback(tape, scaling("10"), std::nullopt);
  Schedule sc = compress_schedule(p, 1000000);
  test::expect_codec_round_trip(sc.items);
  const uint8_t junk[] = {0xf3, 0x01};
  size_t jp = 0;
  QueueItem x;
  EXPECT_FALSE(ItemCodec{}.decode(junk, sizeof junk, jp, x));
  EXPECT_EQ(jp, 0u);
}


// ------------------------------------------------------------------------------------------- tool events

using test::kLiftDownNs;
using test::kLiftUpNs;
using test::lifting_tape;

// A lifting tape's plan: the tool's state at the start (down: the tape's header says nothing else), then the
// tape's two events, each between the steps the tape has it between.
TEST(PlayerTool, PlanHasTheStartStateAndEveryEventBetweenItsSteps) {
  const PlayPlan p = plan_playback(lifting_tape(), scaling("1"), std::nullopt);
  ASSERT_EQ(p.steps.size(), 500u);
  ASSERT_EQ(p.tools.size(), 3u);
  EXPECT_TRUE(p.tools[0].down);
  EXPECT_EQ(p.tools[0].t, 0u);
  EXPECT_EQ(p.tools[0].before, 0u);
  EXPECT_FALSE(p.tools[1].down);
  EXPECT_EQ(p.tools[1].t, kLiftUpNs);
  EXPECT_EQ(p.tools[1].before, 200u);
  EXPECT_TRUE(p.tools[2].down);
  EXPECT_EQ(p.tools[2].t, kLiftDownNs);
  EXPECT_EQ(p.tools[2].before, 300u);
  // a tape without tool events has no tool items
  EXPECT_TRUE(plan_playback(example_tape("circle"), scaling("1"), std::nullopt).tools.empty());
}

// Every step and tool item of the schedule at its tick: a tool item at its scaled tape time plus the dwells of the
// items before it, rounded down; each step within one tick of its scaled time plus the dwells before it, the steps
// before a tool item at or before its tick, those after it later. Times from the tape's construction, in 1 us
// ticks of a controller.
TEST(PlayerTool, ScheduleWaitsTheDwellAfterEachToolItem) {
  const std::vector<test::TapeStep> tape = test::read_tape(lifting_tape());
  for (const auto& [speed, K] : {std::pair<const char*, double>{"1", 1.0}, {"4", 4.0}, {"2/3", 2.0 / 3.0}})
    for (const double dwell_s : {0.0, 0.005, 0.2}) {
      PlayPlan p = plan_playback(lifting_tape(), scaling(speed), std::nullopt);
      p.tool_dwell_s = dwell_s;
      const Schedule sc = compress_schedule(p, 1000000);
      const double dwell_us = dwell_s * 1e6;
      const double exact_tool[3] = {0.0, kLiftUpNs / 1e3 / K + dwell_us, kLiftDownNs / 1e3 / K + 2 * dwell_us};
      const bool down[3] = {true, false, true};
      std::vector<uint64_t> tool_tick;
      for (const QueueItem& it : sc.items)
        if (it.kind == ItemKind::tool) {
          ASSERT_LT(tool_tick.size(), 3u);
          EXPECT_EQ(it.dir > 0, down[tool_tick.size()]);
          tool_tick.push_back(it.wait);
        }
      ASSERT_EQ(tool_tick.size(), 3u) << speed << " " << dwell_s;
      EXPECT_EQ(sc.tools, 3u);
      for (int j = 0; j < 3; ++j) {
        EXPECT_LE(static_cast<double>(tool_tick[j]), exact_tool[j] + 1e-6) << j;
        EXPECT_GT(static_cast<double>(tool_tick[j]), exact_tool[j] - 1.0) << j;
      }
      const std::vector<uint64_t> ticks[2] = {execute_axis(sc.items, 0), execute_axis(sc.items, 1)};
      size_t k[2] = {0, 0};
      for (size_t i = 0; i < tape.size(); ++i) {
        const int a = tape[i].axis;
        ASSERT_LT(k[a], ticks[a].size());
        const uint64_t tick = ticks[a][k[a]++];
        const int before = i < 200 ? 1 : i < 300 ? 2 : 3;  // tool items before step i
        const double exact = static_cast<double>(tape[i].t) / 1e3 / K + before * dwell_us;
        EXPECT_LE(std::fabs(static_cast<double>(tick) - exact), 1.0 + 1e-9) << "step " << i << " " << speed << " " << dwell_s;
        if (before < 3) {
          EXPECT_LE(tick, tool_tick[before]) << "step " << i;
        }
        EXPECT_GT(tick, tool_tick[before - 1]) << "step " << i;
      }
      EXPECT_EQ(k[0] + k[1], 500u);
    }
}

// A play resumed after step N starts with the tool in the state the events before step N left it in, and the
// later events follow at their times from step N.
TEST(PlayerTool, ResumeStartsWithTheToolStateAtTheResumePoint) {
  const PlayPlan p = plan_playback(lifting_tape(), scaling("1"), std::nullopt);
  struct Case {
    uint64_t done;
    bool start_down;
    std::vector<std::pair<uint64_t, bool>> later;  // (before, down)
  };
  for (const Case& c : {Case{150, true, {{50, false}, {150, true}}}, Case{200, false, {{100, true}}},
                        Case{250, false, {{50, true}}}, Case{300, true, {}}, Case{499, true, {}}}) {
    const PlayPlan r = resume_plan(p, c.done);
    ASSERT_EQ(r.tools.size(), 1 + c.later.size()) << c.done;
    EXPECT_EQ(r.tools[0].down, c.start_down) << c.done;
    EXPECT_EQ(r.tools[0].t, 0u);
    EXPECT_EQ(r.tools[0].before, 0u);
    const uint64_t t0 = p.steps[c.done - 1].t;
    for (size_t j = 0; j < c.later.size(); ++j) {
      EXPECT_EQ(r.tools[j + 1].before, c.later[j].first) << c.done;
      EXPECT_EQ(r.tools[j + 1].down, c.later[j].second) << c.done;
      EXPECT_EQ(r.tools[j + 1].t, (c.later[j].second ? kLiftDownNs : kLiftUpNs) - t0) << c.done;
    }
    // the first schedule item is the tool's state, at tick 0
    const Schedule sc = compress_schedule(r, 1000000);
    ASSERT_FALSE(sc.items.empty());
    EXPECT_EQ(sc.items[0].kind, ItemKind::tool);
    EXPECT_EQ(sc.items[0].wait, 0u);
    EXPECT_EQ(sc.items[0].dir > 0, c.start_down);
  }
}

// Tool items on the wire: the tag (kind 3, bit 3 down) and the tick as a varint, by hand; a tool tag with the axis
// bit set is refused.
TEST(PlayerTool, ToolItemBytesByHand) {
  QueueItem down;
  down.kind = ItemKind::tool;
  down.dir = 1;
  down.wait = 300;  // varint 0xac 0x02
  QueueItem up = down;
  up.dir = -1;
  up.wait = 5;
  ItemCodec enc;
  std::string bytes;
  enc.encode(down, bytes);
  enc.encode(up, bytes);
  EXPECT_EQ(bytes, std::string("\x0e\xac\x02\x06\x05", 5));
  test::expect_codec_round_trip({down, up});
  ItemCodec dec;
  size_t pos = 0;
  QueueItem got;
  ASSERT_TRUE(dec.decode(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), pos, got));
  EXPECT_EQ(got.kind, ItemKind::tool);
  EXPECT_EQ(got.dir, 1);
  EXPECT_EQ(got.wait, 300u);
  const uint8_t odd[] = {0x07, 0x05};
  pos = 0;
  EXPECT_FALSE(ItemCodec{}.decode(odd, sizeof odd, pos, got));
}

}  // namespace tu_machine_player_test_player
}  // namespace polarcam
