// Step/dir decoding and the tape comparison: the decoder on hand-made level sequences (edges, polarity,
// glitches), hand-written VCDs of known steps decoded into steps at times worked out here from the file's
// timestamps (with and without an origin signal, a direction set late, an inverted axis, unknown levels), bad
// input refused in one line, and two hand-made tapes compared (the same steps scaled in time, on a controller's
// tick grid, a step missing, a wrong direction, simultaneous steps in either order, an extra step).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "cam/error.hpp"
#include "capture/capture.hpp"
#include "capture/tape_compare.hpp"
#include "capture/vcd.hpp"
#include "tests/helpers.hpp"
#include "digitizer/tape.hpp"
#include "tests/temp_path.hpp"

namespace polarcam {
namespace tu_capture_test_step_dir {  // named: the test files compile together

// The steps a decoder emits, with their times (tests/helpers.hpp).
using Step = test::Recorded;
using Recorder = test::RecordingSink;

// ---- the decoder ----------------------------------------------------------------------------------------------

// Feeds (STEP, DIR) levels (-1 unknown) to a decoder; returns +1 / -1 per step, 0 for none, 9 for a glitch.
std::vector<int> feed(StepDirDecoder& d, const std::vector<std::pair<int, int>>& sd) {
  std::vector<int> out;
  d.start(sd[0].first, sd[0].second);
  for (size_t i = 1; i < sd.size(); ++i) {
    int dir = 0;
    const auto r = d.update(sd[i].first, sd[i].second, dir);
    out.push_back(r == StepDirDecoder::glitch ? 9 : dir);
  }
  return out;
}

TEST(StepDir, ARisingEdgeIsOneStepItsSignFromDir) {
  StepDirDecoder d;
  // rise with DIR high (+1), fall (nothing), DIR low alone (nothing), rise (-1), stay high (nothing), fall
  EXPECT_EQ(feed(d, {{0, 1}, {1, 1}, {0, 1}, {0, 0}, {1, 0}, {1, 1}, {0, 1}}),
            (std::vector<int>{1, 0, 0, -1, 0, 0}));
  // a STEP high at the start is no step: only a rise from 0 counts
  EXPECT_EQ(feed(d, {{1, 1}, {1, 0}, {0, 0}, {1, 0}}), (std::vector<int>{0, 0, -1}));
}

TEST(StepDir, InvertedPolarity) {
  StepDirDecoder d(true);
  EXPECT_EQ(feed(d, {{0, 1}, {1, 1}, {0, 1}, {1, 0}}), (std::vector<int>{-1, 0, 1}));
}

TEST(StepDir, UnknownLevelsAtAnEdgeAreGlitches) {
  StepDirDecoder d;
  // DIR unknown at a rise: glitch; DIR known again: +1; STEP unknown then 1: glitch (no rise from 0 seen);
  // STEP unknown then 0 then 1: -1... with DIR low
  EXPECT_EQ(feed(d, {{0, 0}, {0, -1}, {1, -1}, {0, -1}, {0, 1}, {1, 1}, {-1, 1}, {1, 1}, {-1, 0}, {0, 0}, {1, 0}}),
            (std::vector<int>{0, 9, 0, 0, 1, 0, 9, 0, 0, -1}));
}

// ---- hand-written recordings ------------------------------------------------------------------------------------

// Timescale 10 ns. Line numbers are given beside the lines that matter.
const char* kRun =
    "$timescale 10 ns $end\n"                // 1
    "$scope module board $end\n"             // 2
    "$var wire 1 ! r_step $end\n"            // 3
    "$var wire 1 \" r_dir $end\n"            // 4
    "$var wire 1 # theta_step $end\n"        // 5
    "$var wire 1 $ theta_dir $end\n"         // 6
    "$var wire 1 % run $end\n"               // 7
    "$upscope $end\n"                        // 8
    "$enddefinitions $end\n"                 // 9
    "$dumpvars\nx!\nx\"\nx#\nx$\nx%\n$end\n"  // 10..16
    "#10\n0!\n0\"\n0#\n0$\n0%\n"             // 17..22: all four known at 100 ns
    "#100\n1%\n"                             // 23..24: run rises at 1000 ns
    "#150\n1\"\n"                            // r_dir high at 1500 ns
    "#400\n1!\n"                             // 27..28: radial + at 4000 ns
    "#420\n0!\n"
    "#500\n1#\n"                             // 31..32: angular - at 5000 ns (theta_dir low since the start)
    "#520\n0#\n"
    "#600\n0\"\n"                            // r_dir low at 6000 ns
    "#700\n1!\n"                             // radial - at 7000 ns, 1000 ns after its DIR change
    "#705\n0!\n"
    "#800\n1$\n1#\n"                         // 41..43: angular + at 8000 ns, DIR changed at the same time
    "#810\n0#\n"
    "#870\n1\"\n"                            // r_dir high at 8700 ns
    "#900\n1!\n"                             // 48..49: radial + at 9000 ns, 300 ns after its DIR change
    "#920\n0!\n"
    "#1000\n";

CaptureResult decode(const std::string& text, CaptureOptions o, Recorder& rec) {
  std::istringstream in(text);
  return decode_capture(in, "run.vcd", CaptureFormat::vcd, o, &rec);
}

CaptureOptions step_dir(const std::string& origin = "") {
  CaptureOptions o;
  o.encoding = CaptureEncoding::step_dir;
  o.origin_signal = origin;
  return o;
}

TEST(StepDirDecode, KnownStepsAtTheirTimesFromTheOriginSignal) {
  Recorder rec;
  const CaptureResult r = decode(kRun, step_dir("run"), rec);
  // the edges' times (timestamp x 10 ns) less the run signal's rising edge (#100: 1000 ns)
  const std::vector<Step> want = {{0, +1, 4000 - 1000},
                                  {1, -1, 5000 - 1000},
                                  {0, -1, 7000 - 1000},
                                  {1, +1, 8000 - 1000},
                                  {0, +1, 9000 - 1000}};
  EXPECT_EQ(rec.steps, want);
  EXPECT_EQ(r.encoding, CaptureEncoding::step_dir);
  EXPECT_EQ(r.origin_signal, "board.run");
  EXPECT_EQ(r.matched, (std::vector<std::string>{"board.r_step", "board.r_dir", "board.theta_step", "board.theta_dir"}));
  EXPECT_EQ(r.origin_fs, static_cast<capture_i128>(1000) * 1000000);
  EXPECT_EQ(r.steps_plus[0], 2u);
  EXPECT_EQ(r.steps_minus[0], 1u);
  EXPECT_EQ(r.steps_plus[1], 1u);
  EXPECT_EQ(r.steps_minus[1], 1u);
  EXPECT_EQ(r.end[0] - r.start[0], 1);
  EXPECT_EQ(r.end[1] - r.start[1], 0);
  EXPECT_EQ(r.illegal_total, 0u);
  EXPECT_EQ(r.duration_ns, 10000 - 1000);  // the last #time, 10 000 ns
  // the direction set late (default setup 650 ns): the angular step at 8000 ns (DIR at the same time) and the
  // radial one at 9000 ns (300 ns after); the radial step 1000 ns after its DIR change is in time
  EXPECT_EQ(r.dir_setup_late[0], 1u);
  EXPECT_EQ(r.dir_setup_late[1], 1u);
  EXPECT_EQ(r.dir_setup_late_first_ns, 8000 - 1000);
  EXPECT_EQ(r.dir_setup_late_first_line, 43u);
  // a setup time of 250 ns: only the simultaneous change is late; of 1001 ns: the 1000 ns one too
  CaptureOptions o = step_dir("run");
  o.dir_setup_ns = 250;
  Recorder r2;
  CaptureResult a = decode(kRun, o, r2);
  EXPECT_EQ(a.dir_setup_late[0] + a.dir_setup_late[1], 1u);
  o.dir_setup_ns = 1001;
  a = decode(kRun, o, r2);
  EXPECT_EQ(a.dir_setup_late[0], 2u);
  EXPECT_EQ(r2.steps.size(), 10u);  // the steps are the same however late the direction came
}

TEST(StepDirDecode, WithoutAnOriginSignalTimeZeroIsTheFirstFullyKnownSample) {
  Recorder rec;
  decode(kRun, step_dir(), rec);
  ASSERT_EQ(rec.steps.size(), 5u);
  EXPECT_EQ(rec.steps[0], (Step{0, +1, 4000 - 100}));  // #10: 100 ns
  EXPECT_EQ(rec.steps[4], (Step{0, +1, 9000 - 100}));
}

TEST(StepDirDecode, DirPolarityInvertedPerAxis) {
  CaptureOptions o = step_dir("run");
  o.invert_dir[0] = true;
  Recorder rec;
  decode(kRun, o, rec);
  const std::vector<Step> want = {{0, -1, 3000}, {1, -1, 4000}, {0, +1, 6000}, {1, +1, 7000}, {0, -1, 8000}};
  EXPECT_EQ(rec.steps, want);
}

TEST(StepDirDecode, SignalsRenamed) {
  std::string text = kRun;
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {" r_step ", " X_STEP "}, {" theta_dir ", " Y_DIR "}, {" run ", " LED "}}) {
    text.replace(text.find(from), from.size(), to);
  }
  CaptureOptions o = step_dir("LED");
  o.signals = parse_capture_signals("r_step=X_STEP,theta_dir=board.Y_DIR", CaptureEncoding::step_dir);
  Recorder rec;
  const CaptureResult r = decode(text, o, rec);
  EXPECT_EQ(rec.steps.size(), 5u);
  EXPECT_EQ(r.matched[0], "board.X_STEP");
  EXPECT_EQ(r.matched[3], "board.Y_DIR");
}

const char* kGlitches =
    "$timescale 10 ns $end\n"            // 1
    "$var wire 1 ! r_step $end\n"        // 2
    "$var wire 1 \" r_dir $end\n"        // 3
    "$var wire 1 # theta_step $end\n"    // 4
    "$var wire 1 $ theta_dir $end\n"     // 5
    "$enddefinitions $end\n"             // 6
    "#0\n0!\n0\"\n0#\n0$\n"              // 7..11
    "#100\nx\"\n"                        // 12..13: r_dir unknown at 1000 ns
    "#200\n1!\n"                         // 14..15: radial STEP rises with DIR unknown: glitch at 2000 ns
    "#300\n0!\n"
    "#350\n1\"\n"                        // r_dir high again
    "#400\n1!\n"                         // radial + at 4000 ns
    "#500\n0!\n"
    "#600\nz#\n"                         // theta_step unknown at 6000 ns
    "#700\n1#\n"                         // 26..27: theta_step 1 out of an unknown level: glitch at 7000 ns
    "#800\n0#\n"
    "#900\n1#\n"                         // angular - at 9000 ns
    "#950\n";

TEST(StepDirDecode, GlitchesAreReportedWithTimeAndLineAndGiveNoStep) {
  Recorder rec;
  const CaptureResult r = decode(kGlitches, step_dir(), rec);
  EXPECT_EQ(rec.steps, (std::vector<Step>{{0, +1, 4000}, {1, -1, 9000}}));
  EXPECT_EQ(r.illegal_total, 2u);
  EXPECT_EQ(r.illegal_axis[0], 1u);
  EXPECT_EQ(r.illegal_axis[1], 1u);
  ASSERT_EQ(r.illegal.size(), 2u);
  EXPECT_EQ(r.illegal[0].t_ns, 2000);
  EXPECT_EQ(r.illegal[0].line, 15u);
  EXPECT_EQ(r.illegal[0].axis, 0);
  EXPECT_EQ(transition_levels(r.illegal[0].from, r.illegal[0].unknown_from), "0x");
  EXPECT_EQ(transition_levels(r.illegal[0].to, r.illegal[0].unknown_to), "1x");
  EXPECT_EQ(r.illegal[1].t_ns, 7000);
  EXPECT_EQ(r.illegal[1].line, 27u);
  EXPECT_EQ(r.illegal[1].axis, 1);
  EXPECT_EQ(transition_levels(r.illegal[1].from, r.illegal[1].unknown_from), "x0");
  EXPECT_EQ(transition_levels(r.illegal[1].to, r.illegal[1].unknown_to), "10");
  // the quadrature encoding still refuses a channel that goes back to x
  CaptureOptions q;
  q.signals = parse_capture_signals("r_a=r_step,r_b=r_dir,theta_a=theta_step,theta_b=theta_dir");
  std::istringstream in(kGlitches);
  try {
    decode_capture(in, "q.vcd", CaptureFormat::vcd, q, nullptr);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("q.vcd:13: signal goes to x"), std::string::npos) << e.what();
  }
}

std::string error_of(const std::string& text, const CaptureOptions& o) {
  try {
    Recorder rec;
    decode(text, o, rec);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(StepDirDecode, BadInputIsOneLineNamingWhatToChange) {
  const std::vector<std::string> errors = {
      // an origin signal that never rises
      error_of(std::string(kRun).substr(0, std::string(kRun).find("#100\n")), step_dir("run")),
      // a step before the origin's edge (the run signal rises only at the end)
      error_of([] {
        std::string t = kRun;
        t.replace(t.find("#100\n1%"), 7, "#100\n0%");
        t.replace(t.find("#1000\n"), 6, "#1000\n1%\n#1100\n");
        return t;
      }(), step_dir("run")),
      // a signal the file does not have
      error_of(kRun, step_dir("enable")),
  };
  EXPECT_NE(errors[0].find("run.vcd: the origin signal 'run' never rises"), std::string::npos) << errors[0];
  EXPECT_NE(errors[1].find("run.vcd:28: a step before the first rising edge of the origin signal 'run'"),
            std::string::npos)
      << errors[1];
  EXPECT_NE(errors[2].find("no signal named 'enable'"), std::string::npos) << errors[2];
  for (const std::string& e : errors) EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  // channels of the other encoding, unknown channels, encodings
  try {
    parse_capture_signals("r_a=D0", CaptureEncoding::step_dir);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("give --encoding quadrature"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_capture_signals("r_step=D0"), InputError);
  EXPECT_THROW(parse_capture_signals("r_pulse=D0", CaptureEncoding::step_dir), InputError);
  EXPECT_EQ(parse_capture_encoding("step-dir"), CaptureEncoding::step_dir);
  EXPECT_EQ(parse_capture_encoding("quadrature"), CaptureEncoding::quadrature);
  EXPECT_THROW(parse_capture_encoding("stepdir"), InputError);
  EXPECT_EQ(capture_channels(CaptureEncoding::step_dir),
            (std::vector<std::string>{"r_step", "r_dir", "theta_step", "theta_dir"}));
  CaptureOptions o = step_dir();
  o.dir_setup_ns = -1;
  EXPECT_NE(error_of(kRun, o).find("--dir-setup"), std::string::npos);
}

// ---- comparing tapes ----------------------------------------------------------------------------------------------

void write_tape(const std::string& path, const std::vector<Step>& steps) {
  TapeHeader h;
  h.res[0] = 2.54e-5;
  h.res[1] = 2 * std::numbers::pi / 16000;
  h.steps_per_rev = 16000;
  h.provenance = "{\"test\":1}";
  TapeWriter w(path, h);
  int64_t node[2] = {0, 0};
  for (const Step& s : steps) {
    w.step(s.axis, s.dir, s.t_ns);
    node[s.axis] += s.dir;
  }
  h.end[0] = node[0];
  h.end[1] = node[1];
  h.duration_ticks = steps.empty() ? 0 : static_cast<uint64_t>(steps.back().t_ns);
  w.finish(h);
}

struct Tapes {
  std::string expected = test::temp_path("expected.tape"), seen = test::temp_path("seen.tape");
  ~Tapes() {
    std::remove(expected.c_str());
    std::remove(seen.c_str());
  }
  TapeComparison compare(const std::vector<Step>& seen_steps, const TapeCompareOptions& o) {
    write_tape(seen, seen_steps);
    return compare_tapes(expected, seen, o);
  }
};

// The expected tape: played at speed scale 2, its steps are due at half these times.
const std::vector<Step> kExpected = {{0, +1, 10000}, {1, +1, 25000}, {0, -1, 40000}, {1, +1, 60000}, {0, +1, 61000}};

TapeCompareOptions at_speed_2(int64_t tick_ns, int64_t tolerance_ns) {
  TapeCompareOptions o;
  o.speed_num = 2;
  o.tick_ns = tick_ns;
  o.tolerance_ns = tolerance_ns;
  return o;
}

TEST(CompareTapes, TheSameStepsAtTheScaledTimes) {
  Tapes t;
  write_tape(t.expected, kExpected);
  const TapeComparison c =
      t.compare({{0, +1, 5000}, {1, +1, 12500}, {0, -1, 20000}, {1, +1, 30000}, {0, +1, 30500}}, at_speed_2(0, 0));
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.steps_expected, 5u);
  EXPECT_EQ(c.steps_seen, 5u);
  EXPECT_EQ(c.matched, 5u);
  EXPECT_EQ(c.max_time_error_ns, 0.0);
  // at speed scale 1 every time is off by its half: the largest 30 500 ns (the last step)
  TapeCompareOptions one;
  one.tolerance_ns = 30499;
  const TapeComparison d = compare_tapes(t.expected, t.seen, one);
  EXPECT_EQ(d.max_time_error_ns, 30500.0);
  EXPECT_EQ(d.worst_step, 5u);
  EXPECT_EQ(d.time_mismatches, 1u);  // only the last is beyond 30 499 ns
  EXPECT_FALSE(d.ok());
}

TEST(CompareTapes, OnAControllersTickGrid) {
  Tapes t;
  write_tape(t.expected, kExpected);
  // fired on ticks of 4 us (1, 3, 5, 7, 8) each some ns after its tick (the interrupt's latency)
  const std::vector<Step> seen = {{0, +1, 4300}, {1, +1, 12100}, {0, -1, 20000}, {1, +1, 28380}, {0, +1, 32050}};
  TapeComparison c = t.compare(seen, at_speed_2(4000, 4000));
  EXPECT_TRUE(c.ok());
  // on their ticks against 5000, 12500, 20000, 30000, 30500: 1000, 500, 0, 2000, 1500
  EXPECT_EQ(c.max_time_error_ns, 2000.0);
  EXPECT_EQ(c.worst_step, 4u);
  // as seen: 700, 400, 0, 1620, 1550
  EXPECT_EQ(c.max_raw_error_ns, 1620.0);
  EXPECT_EQ(c.max_jitter_ns, 380.0);
  // a tolerance below 2000 ns: step 4 is late
  c = compare_tapes(t.expected, t.seen, at_speed_2(4000, 1999));
  EXPECT_EQ(c.time_mismatches, 1u);
  EXPECT_EQ(c.matched, 4u);
  ASSERT_EQ(c.listed.size(), 1u);
  EXPECT_EQ(c.listed[0].kind, TapeMismatch::time);
  EXPECT_EQ(c.listed[0].index, 4u);
  EXPECT_EQ(c.listed[0].error_ns, 2000.0);
  EXPECT_EQ(c.listed[0].expected_ns, 30000.0);
  EXPECT_EQ(c.listed[0].seen_ns, 28380);
}

TEST(CompareTapes, AMissingStepAWrongDirectionAnExtraStep) {
  Tapes t;
  write_tape(t.expected, kExpected);
  // step 3 (radial -) missing: steps 3 and 4 compare with the wrong axes, step 5 is missing
  TapeComparison c = t.compare({{0, +1, 5000}, {1, +1, 12500}, {1, +1, 30000}, {0, +1, 30500}}, at_speed_2(0, 10));
  EXPECT_EQ(c.steps_expected, 5u);
  EXPECT_EQ(c.steps_seen, 4u);
  EXPECT_EQ(c.order_mismatches, 2u);
  EXPECT_EQ(c.mismatches(), 3u);
  EXPECT_FALSE(c.ok());
  ASSERT_EQ(c.listed.size(), 3u);
  EXPECT_EQ(c.listed[0].kind, TapeMismatch::order);
  EXPECT_EQ(c.listed[0].index, 3u);
  EXPECT_EQ(c.listed[0].expected_axis, 0);
  EXPECT_EQ(c.listed[0].expected_dir, -1);
  EXPECT_EQ(c.listed[0].seen_axis, 1);
  EXPECT_EQ(c.listed[2].kind, TapeMismatch::missing);
  EXPECT_EQ(c.listed[2].index, 5u);
  // step 3 in the wrong direction
  c = t.compare({{0, +1, 5000}, {1, +1, 12500}, {0, +1, 20000}, {1, +1, 30000}, {0, +1, 30500}}, at_speed_2(0, 10));
  EXPECT_EQ(c.order_mismatches, 1u);
  EXPECT_EQ(c.mismatches(), 1u);
  EXPECT_EQ(c.listed.at(0).seen_dir, +1);
  // a sixth step
  c = t.compare({{0, +1, 5000}, {1, +1, 12500}, {0, -1, 20000}, {1, +1, 30000}, {0, +1, 30500}, {0, +1, 31000}},
                at_speed_2(0, 10));
  EXPECT_EQ(c.matched, 5u);
  EXPECT_EQ(c.mismatches(), 1u);
  ASSERT_EQ(c.listed.size(), 1u);
  EXPECT_EQ(c.listed[0].kind, TapeMismatch::extra);
  EXPECT_EQ(c.listed[0].index, 6u);
}

TEST(CompareTapes, StepsOfTwoAxesOnOneTickInEitherOrder) {
  Tapes t;
  write_tape(t.expected, kExpected);
  // steps 4 (angular, due 30 000) and 5 (radial, due 30 500) both fired on the tick at 32 000; a recording lists
  // the radial one first
  TapeComparison c =
      t.compare({{0, +1, 5000}, {1, +1, 12500}, {0, -1, 20000}, {0, +1, 32000}, {1, +1, 32000}}, at_speed_2(4000, 4000));
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.simultaneous_swapped, 1u);
  EXPECT_EQ(c.max_time_error_ns, 2000.0);  // the angular step: 32 000 against 30 000
  // on one tick with different latencies (edges 160 ns apart): the same
  c = t.compare({{0, +1, 5000}, {1, +1, 12500}, {0, -1, 20000}, {0, +1, 32040}, {1, +1, 32200}}, at_speed_2(4000, 4000));
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.simultaneous_swapped, 1u);
  EXPECT_EQ(c.max_raw_error_ns, 2200.0);
  // at two different times the order is the recording's: both out of order
  c = t.compare({{0, +1, 5000}, {1, +1, 12500}, {0, -1, 20000}, {0, +1, 31000}, {1, +1, 32000}}, at_speed_2(0, 4000));
  EXPECT_EQ(c.simultaneous_swapped, 0u);
  EXPECT_EQ(c.order_mismatches, 2u);
}

TEST(CompareTapes, TheComparerTakesTheDecodersStepsDirectly) {
  Tapes t;
  // the hand-written run's steps (times from its run signal) as the tape it played, at speed scale 1
  write_tape(t.expected, {{0, +1, 3000}, {1, -1, 4000}, {0, -1, 6000}, {1, +1, 7000}, {0, +1, 8000}});
  TapeCompareOptions o;
  TapeComparer cmp(t.expected, o);
  std::istringstream in(kRun);
  decode_capture(in, "run.vcd", CaptureFormat::vcd, step_dir("run"), &cmp);
  const TapeComparison c = cmp.finish();
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.matched, 5u);
  // bad options are refused naming the option
  o.speed_den = 0;
  EXPECT_THROW(TapeComparer(t.expected, o), InputError);
}

}  // namespace tu_capture_test_step_dir
}  // namespace polarcam
