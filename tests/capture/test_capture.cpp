// The encoder capture: the quadrature decoder on hand-made level sequences (directions, reversals, illegal
// transitions, counts per step), the VCD and CSV readers on hand-written files (and what they refuse, naming the
// line), and decoding with the speed statistics on captures of known motion.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

#include "cam/error.hpp"
#include "capture/capture.hpp"
#include "capture/csv_levels.hpp"
#include "capture/vcd.hpp"
#include "tests/helpers.hpp"
#include "tests/quadrature_writer.hpp"

namespace polarcam {
namespace tu_capture_test_capture {  // named: the test files compile together

// The steps a decoder emits, with their times (tests/helpers.hpp).
using Step = test::Recorded;
using Recorder = test::RecordingSink;

// Feeds (A, B) pairs to a decoder; returns the counts' directions (0 for no change, 9 for illegal).
std::vector<int> feed(QuadratureDecoder& d, const std::vector<std::pair<int, int>>& ab) {
  std::vector<int> out;
  d.start(ab[0].first, ab[0].second);
  for (size_t i = 1; i < ab.size(); ++i) {
    int dir = 0, step = 0;
    const auto r = d.update(ab[i].first, ab[i].second, dir, step);
    out.push_back(r == QuadratureDecoder::illegal ? 9 : dir);
  }
  return out;
}

TEST(Quadrature, ALeadingBCountsUpAndTheReverseCountsDown) {
  QuadratureDecoder d;
  // 00 10 11 01 00: A rises first, B follows: four counts up
  EXPECT_EQ(feed(d, {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}), (std::vector<int>{1, 1, 1, 1}));
  EXPECT_EQ(d.count(), 4);
  // the reverse order: four counts down
  EXPECT_EQ(feed(d, {{0, 0}, {0, 1}, {1, 1}, {1, 0}, {0, 0}}), (std::vector<int>{-1, -1, -1, -1}));
  EXPECT_EQ(d.count(), -4);
  // starting anywhere in the cycle
  EXPECT_EQ(feed(d, {{1, 1}, {0, 1}, {0, 0}, {1, 0}}), (std::vector<int>{1, 1, 1}));
}

TEST(Quadrature, ReversalsAndRepeatedLevels) {
  QuadratureDecoder d;
  // up two, the same levels again (no count), back three, up one
  EXPECT_EQ(feed(d, {{0, 0}, {1, 0}, {1, 1}, {1, 1}, {1, 0}, {0, 0}, {0, 1}, {0, 0}}),
            (std::vector<int>{1, 1, 0, -1, -1, -1, 1}));
  EXPECT_EQ(d.count(), 0);
}

TEST(Quadrature, BothChannelsAtOnceIsIllegalAndLeavesTheCount) {
  QuadratureDecoder d;
  EXPECT_EQ(feed(d, {{0, 0}, {1, 0}, {0, 1}, {0, 0}, {1, 1}, {0, 1}}), (std::vector<int>{1, 9, 1, 9, 1}));
  // +1, illegal (10 -> 01), 01 -> 00 is +1, illegal (00 -> 11), 11 -> 01 is +1
  EXPECT_EQ(d.count(), 3);
}

TEST(Quadrature, CountsPerStepStepsWhenTheCountCrossesAMultiple) {
  QuadratureDecoder d(4);
  d.start(0, 0);
  // the Gray cycle forward: counts 1..8; steps at counts 4 and 8
  const std::pair<int, int> fwd[4] = {{1, 0}, {1, 1}, {0, 1}, {0, 0}};
  std::vector<int> steps;
  for (int i = 0; i < 8; ++i) {
    int dir = 0, step = 0;
    d.update(fwd[i % 4].first, fwd[i % 4].second, dir, step);
    steps.push_back(step);
  }
  EXPECT_EQ(steps, (std::vector<int>{0, 0, 0, 1, 0, 0, 0, 1}));
  EXPECT_EQ(d.step_index(), 2);
  // one count back from 8 (a multiple) is 7: floor(7/4) = 1, a step down at once; forward again: up at 8
  int dir = 0, step = 0;
  d.update(0, 1, dir, step);
  EXPECT_EQ(dir, -1);
  EXPECT_EQ(step, -1);
  d.update(0, 0, dir, step);
  EXPECT_EQ(step, 1);
  // from count 0 one count down is -1: floor(-1/4) = -1, a step down
  QuadratureDecoder e(4);
  e.start(0, 0);
  e.update(0, 1, dir, step);
  EXPECT_EQ(step, -1);
  EXPECT_EQ(e.step_index(), -1);
}

// ---- the VCD reader ----------------------------------------------------------------------------------------

std::vector<LevelSample> read_all(LevelSource& src) {
  std::vector<LevelSample> v;
  LevelSample s;
  while (src.next(s)) v.push_back(s);
  return v;
}

const char* kVcd =
    "$date\n  Mon Jan 1 $end\n"
    "$timescale 10 ns $end\n"
    "$scope module top $end\n"
    "$var wire 1 ! a $end\n"
    "$scope module sub $end\n"
    "$var reg 1 \" b [0] $end\n"
    "$var wire 1 ! a_alias $end\n"
    "$var wire 8 # bus $end\n"
    "$upscope $end\n"
    "$upscope $end\n"
    "$enddefinitions $end\n"
    "#0\n"
    "$dumpvars\nx!\nbx \"\nb00000000 #\n$end\n"   // lines 14..18
    "#5\n1!\nb0 \"\n"                              // a known (1), b known (0)
    "#7\nb10101010 #\n"                            // only the bus: no sample
    "#9\n0!\n1!\n0!\n"                             // a glitch: 1 -> 0 -> 1 -> 0 at one time (lines 25..27)
    "#12\nb1 \"\n$comment a note $end\nr1.5 $\n"   // real of an unknown id: skipped
    "#20\n";

TEST(Vcd, LevelsTimesAliasesGlitchesAndTheEnd) {
  std::istringstream in(kVcd);
  VcdReader rd(in, "t.vcd", {"a", "top.sub.b"});
  EXPECT_EQ(rd.resolution_fs(), 10000000);  // 10 ns
  EXPECT_EQ(rd.matched(), (std::vector<std::string>{"top.a", "top.sub.b"}));
  const std::vector<LevelSample> s = read_all(rd);
  ASSERT_EQ(s.size(), 5u);
  // #5: a 1, b 0, both known now
  EXPECT_EQ(static_cast<int64_t>(s[0].t_fs), 50000000);
  EXPECT_EQ(s[0].levels, 1u);
  EXPECT_EQ(s[0].known, 3u);
  // #9: a 1 -> 0, then 0 -> 1 (a second change at one time splits the sample), then 1 -> 0
  for (int i = 1; i <= 3; ++i) EXPECT_EQ(static_cast<int64_t>(s[i].t_fs), 90000000);
  EXPECT_EQ(s[1].levels, 0u);
  EXPECT_EQ(s[2].levels, 1u);
  EXPECT_EQ(s[3].levels, 0u);
  EXPECT_EQ(s[3].line, 27u);
  // #12: b rises
  EXPECT_EQ(s[4].levels, 2u);
  EXPECT_EQ(s[4].changed, 2u);
  EXPECT_EQ(static_cast<int64_t>(rd.end_fs()), 200000000);
}

TEST(Vcd, AnAliasOfTheSameWireIsNotAmbiguous) {
  std::istringstream in(kVcd);
  VcdReader rd(in, "t.vcd", {"a_alias", "b"});
  EXPECT_EQ(read_all(rd).size(), 5u);
}

std::string vcd_error(const std::string& text, const std::vector<std::string>& names = {"a", "b"}) {
  try {
    std::istringstream in(text);
    VcdReader rd(in, "bad.vcd", names);
    read_all(rd);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

const char* kHead = "$timescale 1ns $end\n$var wire 1 ! a $end\n$var wire 1 \" b $end\n$enddefinitions $end\n";

TEST(Vcd, RefusesNamingTheLine) {
  EXPECT_NE(vcd_error(std::string(kHead) + "#0\n0!\n0\"\n#10\n1!\n#5\n0!\n").find("bad.vcd:10: time #5 goes back"),
            std::string::npos);
  EXPECT_NE(vcd_error(kHead, {"a", "c"}).find("bad.vcd:4: no signal named 'c'; the file's signals are a, b"),
            std::string::npos);
  EXPECT_NE(vcd_error("$timescale 1ns $end\n$var wire 2 ! a $end\n$var wire 1 \" b $end\n$enddefinitions $end\n")
                .find("bad.vcd:2: signal 'a' is 2 bits wide"),
            std::string::npos);
  EXPECT_NE(vcd_error(std::string(kHead) + "#0\n0!\n#3\nx!\n").find("bad.vcd:8: signal goes to x"),
            std::string::npos);
  EXPECT_NE(vcd_error(std::string(kHead) + "#0\n0!\nhello\n").find("bad.vcd:7: 'hello' is not a timestamp"),
            std::string::npos);
  EXPECT_NE(vcd_error("$timescale 1ns $end\n$var wire 1 ! a $end\n").find("no $enddefinitions"), std::string::npos);
  EXPECT_NE(vcd_error("$timescale 3 parsecs $end\n").find("bad.vcd:1: timescale '3parsecs'"), std::string::npos);
  EXPECT_NE(vcd_error(std::string(kHead) + "#0\nb10 !\n").find("more than one bit"), std::string::npos);
  EXPECT_NE(vcd_error("$scope module x $end\n$var wire 1 ! a $end\n$upscope $end\n$scope module y $end\n"
                      "$var wire 1 \" a $end\n$upscope $end\n$enddefinitions $end\n",
                      {"a"})
                .find("ambiguous"),
            std::string::npos);
  EXPECT_NE(vcd_error("garbage").find("bad.vcd:1:"), std::string::npos);
  EXPECT_NE(vcd_error("").find("no $enddefinitions"), std::string::npos);
}

// ---- the CSV reader ----------------------------------------------------------------------------------------

TEST(Csv, ColumnsByNameCommentsQuotesExponentsAndTheResolution) {
  std::istringstream in(
      "; sigrok style comment\n"
      "\n"
      "\"b\", time_s ,x, a\n"
      "1,-0.5,9,0\n"           // line 4: before the trigger
      "1,-0.5,7,0\n"           // nothing asked for changes: no sample
      "0,1.25e-4,7,1\n"        // line 6: 125 us, both change
      "# a comment row\n"
      "0,0.000125000,7,0\n");  // line 8: 9 decimals: resolution 1 ns
  CsvLevelReader rd(in, "t.csv", {"a", "b"});
  const std::vector<LevelSample> s = read_all(rd);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(static_cast<int64_t>(s[0].t_fs), -500000000000000);
  EXPECT_EQ(s[0].levels, 2u);
  EXPECT_EQ(s[0].line, 4u);
  EXPECT_EQ(static_cast<int64_t>(s[1].t_fs), 125000000000);
  EXPECT_EQ(s[1].levels, 1u);
  EXPECT_EQ(s[1].changed, 3u);
  EXPECT_EQ(s[2].line, 8u);
  EXPECT_EQ(rd.resolution_fs(), 1000000);
  EXPECT_EQ(static_cast<int64_t>(rd.end_fs()), 125000000000);
}

std::string csv_error(const std::string& text) {
  try {
    std::istringstream in(text);
    CsvLevelReader rd(in, "bad.csv", {"a", "b"});
    read_all(rd);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Csv, RefusesNamingTheLine) {
  EXPECT_NE(csv_error("time_s,a\n0,1\n").find("bad.csv:1: no column 'b'"), std::string::npos);
  EXPECT_NE(csv_error("t,a,b\n").find("no column 'time_s'"), std::string::npos);
  EXPECT_NE(csv_error("time_s,a,b\n0,1,0\n0.1,1,2\n").find("bad.csv:3: '2' is not a level 0 or 1"),
            std::string::npos);
  EXPECT_NE(csv_error("time_s,a,b\n0.2,1,0\n0.1,1,1\n").find("bad.csv:3: time_s 0.1 goes back"), std::string::npos);
  EXPECT_NE(csv_error("time_s,a,b\n0,1\n").find("bad.csv:2: the row has 2 fields"), std::string::npos);
  EXPECT_NE(csv_error("time_s,a,b\nsoon,1,0\n").find("bad.csv:2: time_s 'soon' is not a decimal"), std::string::npos);
  EXPECT_NE(csv_error("time_s,a,b\n1e-16,1,0\n").find("finer than 1 fs"), std::string::npos);
  EXPECT_NE(csv_error("").find("no header row"), std::string::npos);
}

TEST(Csv, DecimalSecondsAreExact) {
  int64_t m = 0;
  int e = 0;
  ASSERT_TRUE(parse_decimal_seconds("0.000125", m, e));
  EXPECT_EQ(m, 125);
  EXPECT_EQ(e, -6);
  ASSERT_TRUE(parse_decimal_seconds("-1.5E+2", m, e));
  EXPECT_EQ(m, -15);
  EXPECT_EQ(e, 1);
  ASSERT_TRUE(parse_decimal_seconds("3.", m, e));
  EXPECT_EQ(m, 3);
  EXPECT_FALSE(parse_decimal_seconds(".", m, e));
  EXPECT_FALSE(parse_decimal_seconds("1e", m, e));
  EXPECT_FALSE(parse_decimal_seconds("1.2.3", m, e));
  EXPECT_FALSE(parse_decimal_seconds("1234567890123456789", m, e));
}

// ---- decoding --------------------------------------------------------------------------------------------

CaptureOptions thesis_options() {
  CaptureOptions o;
  o.grid.dr = 0.0254e-3;
  o.grid.steps_per_rev = 16000;
  o.grid.dtheta = 2 * std::numbers::pi / 16000;
  o.start[0] = 4000;  // r = 10.16 cm
  o.start[1] = 0;
  return o;
}

TEST(Decode, StepsInOrderWithTheirTimesFromTheFirstFullyKnownSample) {
  // r: up, up; theta: down; r and theta at one time; an illegal r transition; then r down
  const std::string vcd =
      "$timescale 1 us $end\n$var wire 1 A r_a $end\n$var wire 1 B r_b $end\n$var wire 1 C theta_a $end\n"
      "$var wire 1 D theta_b $end\n$enddefinitions $end\n"
      "#100\n0A\n0B\n0C\n"   // theta_b still unknown
      "#150\n1D\n"           // line 12: all known: the origin (theta at 01)
      "#200\n1A\n"           // r +1 at 50 us
      "#300\n1B\n0D\n"       // r +1, theta 01 -> 00 is +1: both at 150 us, radial first
      "#400\n0A\n0B\n"       // lines 19..20: r 11 -> 00: illegal at 250 us
      "#500\n1B\n"           // r 00 -> 01: -1 at 350 us
      "#900\n";
  std::istringstream in(vcd);
  CaptureOptions o = thesis_options();
  Recorder rec;
  const CaptureResult r = decode_capture(in, "t.vcd", CaptureFormat::vcd, o, &rec);
  EXPECT_EQ(rec.steps, (std::vector<Step>{{0, 1, 50000}, {0, 1, 150000}, {1, 1, 150000}, {0, -1, 350000}}));
  EXPECT_EQ(static_cast<int64_t>(r.origin_fs), 150000000000);
  EXPECT_EQ(r.duration_ns, 750000);
  EXPECT_EQ(r.resolution_fs, 1000000000);
  EXPECT_EQ(r.illegal_total, 1u);
  ASSERT_EQ(r.illegal.size(), 1u);
  EXPECT_EQ(r.illegal[0].t_ns, 250000);
  EXPECT_EQ(r.illegal[0].axis, 0);
  EXPECT_EQ(r.illegal[0].line, 20u);
  EXPECT_EQ(r.illegal[0].from, 0b11);
  EXPECT_EQ(r.illegal[0].to, 0b00);
  EXPECT_EQ(r.counts_plus[0], 2u);
  EXPECT_EQ(r.counts_minus[0], 1u);
  EXPECT_EQ(r.counts_plus[1], 1u);
  EXPECT_EQ(r.end[0], 4001);
  EXPECT_EQ(r.end[1], 1);
}

TEST(Decode, NoFullyKnownSampleIsRefused) {
  std::istringstream in("time_s,r_a,r_b,theta_a\n0,0,0,0\n");
  try {
    CsvLevelReader rd(in, "x.csv", {"r_a", "r_b", "theta_a", "theta_b"});
    FAIL() << "the missing column was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no column 'theta_b'"), std::string::npos);
  }
  std::istringstream vcd("$var wire 1 A r_a $end\n$var wire 1 B r_b $end\n$var wire 1 C theta_a $end\n"
                         "$var wire 1 D theta_b $end\n$enddefinitions $end\n#0\n0A\n0B\n0C\n");
  EXPECT_THROW(decode_capture(vcd, "y.vcd", CaptureFormat::vcd, thesis_options(), nullptr), InputError);
}

// A radial line traced outwards: `steps` radial steps, the k-th at t_k; speed over windows of N steps is
// N dR / (t_{k+N} - t_k) exactly.
TEST(Decode, SpeedOfARadialTraceAndWhereItVaried) {
  std::vector<test::QStep> steps;
  int64_t t = 0;
  const int64_t slow_from = 400, slow_to = 600;  // steps traced at half the speed
  for (int k = 1; k <= 1000; ++k) {
    t += (k > slow_from && k <= slow_to) ? 2000000 : 1000000;  // 1 ms a step, 2 ms in the slow stretch
    steps.push_back({t, 0, 1});
  }
  test::QuadratureWriterOptions w;
  const std::string vcd = test::quadrature_vcd(steps, w, "1 ns");
  std::istringstream in(vcd);
  CaptureOptions o = thesis_options();
  o.window_steps = 100;
  Recorder rec;
  const CaptureResult r = decode_capture(in, "line.vcd", CaptureFormat::vcd, o, &rec);
  ASSERT_EQ(rec.steps.size(), 1000u);
  const double dr = o.grid.dr;
  // windows: from step 1 to 101, 101 to 201, ...: 9 whole windows (step 901 to 1001 does not exist)
  EXPECT_EQ(r.speed.windows, 9u);
  const double fast = 100 * dr / 0.1, slow = 100 * dr / 0.2;
  EXPECT_NEAR(r.speed.max_mps, fast, 1e-12);
  EXPECT_NEAR(r.speed.min_mps, slow, 1e-12);
  EXPECT_NEAR(r.speed.median_mps, fast, 1e-12);
  // the mean is the distance over the time: 900 steps from step 1 to 901 (t_1 = 1 ms, t_901 = 1101 ms)
  EXPECT_NEAR(r.speed.mean_mps, 900 * dr / 1.1, 1e-12);
  ASSERT_EQ(r.speed.varied.size(), 1u);
  // window 301->401: 99 fast steps and one slow one: 101 ms, off the median by 1 %: within 5 %; 401->501 and
  // 501->601 slow; 601->701 fast
  EXPECT_EQ(r.speed.varied_windows, 2u);
  EXPECT_EQ(r.speed.varied[0].from_ns, rec.steps[400].t_ns);
  EXPECT_EQ(r.speed.varied[0].to_ns, rec.steps[600].t_ns);
  EXPECT_NEAR(r.path_length_m, 1000 * dr, 1e-12);
}

TEST(Decode, OptionsAreChecked) {
  std::istringstream in("$var wire 1 A r_a $end\n$var wire 1 B r_b $end\n$var wire 1 C theta_a $end\n"
                        "$var wire 1 D theta_b $end\n$enddefinitions $end\n#0\n0A\n0B\n0C\n0D\n");
  CaptureOptions o = thesis_options();
  o.window_steps = 0;
  EXPECT_THROW(decode_capture(in, "x.vcd", CaptureFormat::vcd, o, nullptr), InputError);
  EXPECT_THROW(parse_capture_signals("r_c=D0"), InputError);
  EXPECT_THROW(parse_capture_signals("r_a"), InputError);
  const CaptureSignals s = parse_capture_signals("r_a=D0,theta_b=top.enc.B");
  EXPECT_EQ(s.r_a, "D0");
  EXPECT_EQ(s.r_b, "r_b");
  EXPECT_EQ(s.theta_b, "top.enc.B");
}

}  // namespace tu_capture_test_capture
}  // namespace polarcam

namespace polarcam {
namespace tu_capture_test_capture {  // named: the test files compile together

// A random walk of both axes (reversals, simultaneous steps of the two axes, bursts), written as quadrature
// edges by the test's writer and decoded back: the same steps, in the same order, each within the resolution.
std::vector<test::QStep> random_walk(uint32_t seed, int n) {
  std::mt19937 rng(seed);
  std::vector<test::QStep> steps;
  int64_t t = 100000;  // room for a step's earlier edges after the first sample
  int dir[2] = {1, 1};
  int64_t last[2] = {-1, -1};
  for (int i = 0; i < n; ++i) {
    const int axis = static_cast<int>(rng() % 2);
    if (rng() % 10 == 0) dir[axis] = -dir[axis];
    const int64_t gap = rng() % 8 == 0 ? 0 : 20000 + static_cast<int64_t>(rng() % 500000);  // 0: at once
    t += gap;
    if (t == last[axis]) t += 20000;  // one axis never steps twice at once
    last[axis] = t;
    steps.push_back({t, axis, dir[axis]});
  }
  std::stable_sort(steps.begin(), steps.end(), [](const test::QStep& a, const test::QStep& b) {
    return a.t_ns != b.t_ns ? a.t_ns < b.t_ns : a.axis < b.axis;  // radial first at one time, as tapes are
  });
  return steps;
}

void expect_round_trip(const std::vector<test::QStep>& steps, const std::vector<Step>& got, int64_t tolerance_ns,
                       bool exact_order) {
  ASSERT_EQ(got.size(), steps.size());
  // each axis's steps: the same directions, in order, each time within the tolerance
  std::vector<size_t> idx[2];
  for (size_t i = 0; i < steps.size(); ++i) idx[steps[i].axis].push_back(i);
  size_t k[2] = {0, 0};
  std::vector<size_t> order;
  for (size_t i = 0; i < got.size(); ++i) {
    const int a = got[i].axis;
    ASSERT_LT(k[a], idx[a].size());
    const test::QStep& want = steps[idx[a][k[a]++]];
    order.push_back(idx[a][k[a] - 1]);
    ASSERT_EQ(got[i].dir, want.dir) << "step " << i;
    ASSERT_LE(std::abs(got[i].t_ns - want.t_ns), tolerance_ns) << "step " << i;
  }
  // the two axes merged: the same order, but where two steps of different axes lie within twice the tolerance
  for (size_t i = 0; i + 1 < order.size(); ++i) {
    if (order[i] < order[i + 1]) continue;
    ASSERT_FALSE(exact_order) << "steps " << i << " and " << i + 1 << " swapped";
    ASSERT_LE(std::abs(steps[order[i]].t_ns - steps[order[i + 1]].t_ns), 2 * tolerance_ns) << "step " << i;
  }
}

TEST(RoundTrip, NoiseFreeEdgesGiveTheStepsExactly) {
  const std::vector<test::QStep> steps = random_walk(7, 3000);
  for (int64_t cps : {1, 4}) {
    SCOPED_TRACE("counts per step " + std::to_string(cps));
    test::QuadratureWriterOptions w;
    w.counts_per_step = cps;
    w.lead_ns = 3000;
    w.start_ns = 12345;  // the capture starts late: the origin is its first sample
    CaptureOptions o = thesis_options();
    o.counts_per_step = cps;
    for (CaptureFormat f : {CaptureFormat::vcd, CaptureFormat::csv}) {
      std::istringstream in(f == CaptureFormat::vcd ? test::quadrature_vcd(steps, w, "1 ns")
                                                    : test::quadrature_csv(steps, w, 9));
      Recorder rec;
      const CaptureResult r = decode_capture(in, "walk", f, o, &rec);
      // times from the origin: the writer's first sample, at start_ns
      expect_round_trip(steps, rec.steps, 0, true);
      EXPECT_EQ(r.illegal_total, 0u);
      EXPECT_EQ(r.resolution_fs, 1000000);
    }
  }
}

TEST(RoundTrip, JitteredEdgesSampledAt1MHzGiveTheStepsWithinTheResolution) {
  const std::vector<test::QStep> steps = random_walk(11, 3000);
  for (int64_t cps : {1, 4}) {
    SCOPED_TRACE("counts per step " + std::to_string(cps));
    test::QuadratureWriterOptions w;
    w.counts_per_step = cps;
    w.lead_ns = 4000;
    w.unit_ns = 1000;   // a 1 MHz analyser
    w.jitter_ns = 300;  // edges moved up to 0.3 us before sampling
    w.seed = 5;
    CaptureOptions o = thesis_options();
    o.counts_per_step = cps;
    for (CaptureFormat f : {CaptureFormat::vcd, CaptureFormat::csv}) {
      std::istringstream in(f == CaptureFormat::vcd ? test::quadrature_vcd(steps, w, "1 us")
                                                    : test::quadrature_csv(steps, w, 6));
      Recorder rec;
      const CaptureResult r = decode_capture(in, "walk", f, o, &rec);
      EXPECT_EQ(r.resolution_fs, 1000000000);
      // within the resolution (1 us): sampling moves an edge by up to half of it, the jitter by 0.3 us
      expect_round_trip(steps, rec.steps, 1000, false);
      EXPECT_EQ(r.illegal_total, 0u);
    }
  }
}

}  // namespace tu_capture_test_capture
}  // namespace polarcam

namespace polarcam {
namespace tu_capture_test_capture {  // named: the test files compile together

// The fuzzing entry point on damaged input: every prefix of a good recording, and the good one with bytes
// overwritten, either decodes or is refused with an InputError (never a crash, a hang or another exception).
TEST(Robustness, TruncatedAndDamagedRecordingsDecodeOrAreRefused) {
  std::vector<test::QStep> steps;
  for (int k = 1; k <= 40; ++k) steps.push_back({k * 100000, k % 3 == 0 ? 1 : 0, k % 7 == 0 ? -1 : 1});
  test::QuadratureWriterOptions w;
  w.counts_per_step = 2;
  for (const CaptureFormat f : {CaptureFormat::vcd, CaptureFormat::csv}) {
    const std::string good = f == CaptureFormat::vcd ? test::quadrature_vcd(steps, w, "1 ns")
                                                     : test::quadrature_csv(steps, w, 9);
    {  // with default options the whole recording decodes (counts_per_step 1: a step per edge written)
      std::istringstream in(good);
      Recorder rec;
      decode_capture(in, "fuzz", f, {}, &rec);
      int init[4];
      int64_t end = 0;
      EXPECT_EQ(rec.steps.size(), test::quadrature_edges(steps, w, init, end).size());
    }
    std::mt19937 rng(3);
    CaptureOptions o = thesis_options();
    o.counts_per_step = 2;
    for (size_t n = 0; n <= good.size(); n += 7) {
      std::string text = good.substr(0, n);
      if (n % 2 && !text.empty()) text[rng() % text.size()] = static_cast<char>(rng() % 256);
      std::istringstream in(text);
      try {
        decode_capture(in, "damaged", f, o, nullptr);
      } catch (const InputError&) {
      }
      std::istringstream again(text);  // the fuzzing call: default options
      try {
        decode_capture(again, "fuzz", f, {}, nullptr);
      } catch (const InputError&) {
      }
    }
  }
}

}  // namespace tu_capture_test_capture
}  // namespace polarcam
