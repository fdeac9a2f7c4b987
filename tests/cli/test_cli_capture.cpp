// `polarcam capture`: a tape digitized from the limacon job is written as quadrature edges by the test's own
// writer (tests/quadrature_writer.hpp, no capture code), to a VCD and a CSV, noise-free and jittered, and decoded
// back into a tape: the same steps in the same order, every time within the recording's resolution; --json's
// counts, speed and illegal transitions; bad recordings refused in one line naming FILE:LINE.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "digitizer/tape.hpp"
#include "tests/cli_runner.hpp"
#include "tests/quadrature_writer.hpp"

namespace tu_cli_test_cli_capture {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;

namespace {

const std::string kSource = POLARCAM_SOURCE_DIR;
const std::string kMachine = kSource + "/examples/machines/fahim1983.toml";

struct Tape {
  std::vector<QStep> steps;
  int64_t start[2] = {0, 0}, end[2] = {0, 0};
  double res[2] = {0, 0};
  polarcam::TapeRule rule = polarcam::TapeRule::nearest;
};

Tape read_tape(const std::string& path) {
  polarcam::TapeReader rd(path);
  Tape t;
  const polarcam::TapeHeader& h = rd.header();
  for (int a = 0; a < 2; ++a) t.start[a] = h.start[a], t.end[a] = h.end[a], t.res[a] = h.res[a];
  t.rule = h.rule;
  polarcam::StepRecord r;
  int64_t now = 0;
  while (rd.next(r)) {
    now += static_cast<int64_t>(r.interval);
    t.steps.push_back({now, r.axis, r.dir});
  }
  return t;
}

// The limacon example digitized once per test process (its steps, start node and grid).
const Tape& limacon(const Scratch& sc) {
  static Tape t;
  static bool done = false;
  if (!done) {
    const std::string tape = sc.path("limacon.tape");
    const CliResult r = run_cli("digitize " + kSource + "/examples/limacon.toml -o " + tape);
    EXPECT_EQ(r.code, 0) << r.err;
    t = read_tape(tape);
    done = true;
  }
  return t;
}

std::string start_option(const Tape& t) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "--start \"%.17g m,%.17g rad\"", static_cast<double>(t.start[0]) * t.res[0],
                static_cast<double>(t.start[1]) * t.res[1]);
  return buf;
}

// Each axis's steps in order with their directions, each within `tol` ns; the merged order the same, but for two
// steps of different axes within 2 tol of each other (their order is not known to better than the resolution).
void expect_same_steps(const std::vector<QStep>& want, const std::vector<QStep>& got, int64_t tol) {
  ASSERT_EQ(got.size(), want.size());
  std::vector<size_t> idx[2];
  for (size_t i = 0; i < want.size(); ++i) idx[want[i].axis].push_back(i);
  size_t k[2] = {0, 0};
  std::vector<size_t> order;
  int64_t worst = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    const int a = got[i].axis;
    ASSERT_LT(k[a], idx[a].size()) << "step " << i;
    const size_t j = idx[a][k[a]++];
    order.push_back(j);
    ASSERT_EQ(got[i].dir, want[j].dir) << "step " << i;
    worst = std::max(worst, std::abs(got[i].t_ns - want[j].t_ns));
    ASSERT_LE(std::abs(got[i].t_ns - want[j].t_ns), tol) << "step " << i;
  }
  for (size_t i = 0; i + 1 < order.size(); ++i) {
    if (order[i] < order[i + 1]) continue;
    ASSERT_GT(tol, 0) << "steps " << i << " and " << i + 1 << " out of order";
    ASSERT_LE(std::abs(want[order[i]].t_ns - want[order[i + 1]].t_ns), 2 * tol) << "step " << i;
  }
  ::testing::Test::RecordProperty("worst_time_error_ns", std::to_string(worst));
}

TEST(CliCapture, NoiseFreeVcdAndCsvDecodeToTheTapesStepsExactly) {
  Scratch sc;
  const Tape& src = limacon(sc);
  ASSERT_GT(src.steps.size(), 1000u);
  QuadratureWriterOptions w;  // 1 ns, no jitter
  w.tail_ns = 5000;
  for (const std::string kind : {"vcd", "csv"}) {
    SCOPED_TRACE(kind);
    const std::string rec = sc.write("run." + kind, kind == "vcd" ? quadrature_vcd(src.steps, w, "1 ns")
                                                                   : quadrature_csv(src.steps, w, 9));
    const std::string out = sc.path(kind + ".tape");
    const CliResult r = run_cli("capture " + rec + " --machine " + kMachine + " -o " + out + " " + start_option(src));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const Tape got = read_tape(out);
    expect_same_steps(src.steps, got.steps, 0);
    EXPECT_EQ(got.rule, polarcam::TapeRule::capture);
    for (int a = 0; a < 2; ++a) {
      EXPECT_EQ(got.start[a], src.start[a]);
      EXPECT_EQ(got.end[a], src.end[a]);
    }
    // the tape plays and measures like any other
    const json j = cli_json("inspect " + out + " --json");
    EXPECT_EQ(j["rule"], "capture");
    EXPECT_NEAR(j["duration_s"].get<double>(), (static_cast<double>(src.steps.back().t_ns) + 5000) * 1e-9, 1e-9);
  }
}

TEST(CliCapture, JitteredEdgesSampledAt1MHzDecodeWithinTheResolution) {
  Scratch sc;
  const Tape& src = limacon(sc);
  QuadratureWriterOptions w;
  w.unit_ns = 1000;    // a 1 MHz logic analyser
  w.jitter_ns = 400;   // every edge moved by up to 0.4 us before it is sampled
  w.lead_ns = 5000;
  w.seed = 3;
  for (const std::string kind : {"vcd", "csv"}) {
    SCOPED_TRACE(kind);
    const std::string rec = sc.write("jit." + kind, kind == "vcd" ? quadrature_vcd(src.steps, w, "1 us")
                                                                   : quadrature_csv(src.steps, w, 6));
    const std::string out = sc.path("jit.tape");
    const json j = cli_json("capture " + rec + " --machine " + kMachine + " -o " + out + " --json " +
                            start_option(src));
    EXPECT_DOUBLE_EQ(j["resolution_s"].get<double>(), 1e-6);
    EXPECT_EQ(j["illegal_transitions"]["total"], 0);
    expect_same_steps(src.steps, read_tape(out).steps, 1000);
  }
}

TEST(CliCapture, CountsPerStepFromTheMachineFile) {
  Scratch sc;
  const Tape& src = limacon(sc);
  const std::string machine =
      sc.write("m4.toml", replace(read_file(kMachine), "[machine]\n", "[machine]\ncounts_per_step = 4\n"));
  QuadratureWriterOptions w;
  w.counts_per_step = 4;
  w.lead_ns = 2000;
  const std::string rec = sc.write("run4.vcd", quadrature_vcd(src.steps, w, "1 ns"));
  const std::string out = sc.path("run4.tape");
  const json j = cli_json("capture " + rec + " --machine " + machine + " -o " + out + " --json " + start_option(src));
  expect_same_steps(src.steps, read_tape(out).steps, 0);
  EXPECT_EQ(j["counts_per_step"], 4);
  // counted independently from the tape: 4 counts per step one way, and the writer's single edge across a
  // multiple the other way are both in the counts; net counts are 4 net steps, less at most 3 left over
  long long net[2] = {0, 0};
  for (const QStep& s : src.steps) net[s.axis] += s.dir;
  EXPECT_LE(std::llabs(j["counts"]["radial"]["net"].get<long long>() - 4 * net[0]), 3);
  EXPECT_LE(std::llabs(j["counts"]["angular"]["net"].get<long long>() - 4 * net[1]), 3);
  // a machine file with a bad counts_per_step is refused naming the key
  const std::string bad = sc.write("m0.toml", replace(read_file(kMachine), "[machine]\n", "[machine]\ncounts_per_step = 0\n"));
  expect_one_line_error(run_cli("capture " + rec + " --machine " + bad), "counts_per_step");
}

TEST(CliCapture, JsonCountsSpeedAndTheLimaconsSpeed) {
  Scratch sc;
  const Tape& src = limacon(sc);
  QuadratureWriterOptions w;
  const std::string rec = sc.write("run.vcd", quadrature_vcd(src.steps, w, "1 ns"));
  const json j = cli_json("capture " + rec + " --machine " + kMachine + " --json " + start_option(src));
  EXPECT_EQ(j["format"], "vcd");
  EXPECT_EQ(j["signals"]["r_a"], "top.enc.r_a");
  EXPECT_DOUBLE_EQ(j["resolution_s"].get<double>(), 1e-9);
  EXPECT_EQ(j["counts_per_step"], 1);
  unsigned long long plus[2] = {0, 0}, minus[2] = {0, 0};
  for (const QStep& s : src.steps) ++(s.dir > 0 ? plus : minus)[s.axis];
  EXPECT_EQ(j["counts"]["radial"]["plus"], plus[0]);
  EXPECT_EQ(j["counts"]["radial"]["minus"], minus[0]);
  EXPECT_EQ(j["counts"]["angular"]["plus"], plus[1]);
  EXPECT_EQ(j["counts"]["angular"]["minus"], minus[1]);
  EXPECT_EQ(j["steps_total"], src.steps.size());
  EXPECT_EQ(j["illegal_transitions"]["total"], 0);
  EXPECT_FALSE(j.contains("tape"));
  // the limacon job is traced at 1.52 cm/s (examples/limacon.toml): the windows' mean and median read it within
  // the quantisation of a window of 100 steps (a step in 100 at each end: 2 %)
  const json& s = j["speed"];
  EXPECT_EQ(s["window_steps"], 100);
  EXPECT_GT(s["windows"].get<int>(), 10);
  EXPECT_NEAR(s["mean_mps"].get<double>(), 0.0152, 0.0152 * 0.02);
  EXPECT_NEAR(s["median_mps"].get<double>(), 0.0152, 0.0152 * 0.02);
  EXPECT_LE(s["min_mps"].get<double>(), s["median_mps"].get<double>());
  EXPECT_GE(s["max_mps"].get<double>(), s["median_mps"].get<double>());
  EXPECT_GE(s["steady_fraction"].get<double>(), 0.0);
  EXPECT_LE(s["steady_fraction"].get<double>(), 1.0);
  // the path: the limacon's length measured through the windows, against the digitizer's own figure
  const json d = cli_json("digitize " + kSource + "/examples/limacon.toml --json");
  EXPECT_NEAR(j["path_length_m"].get<double>(), d["path_length_m"].get<double>(), d["path_length_m"].get<double>() * 0.01);
}

// A recording with the radial encoder's channels changing at once: reported with its time and line, counted,
// warned about on stderr, and the tape still written.
TEST(CliCapture, AnIllegalTransitionIsReportedNotDropped) {
  Scratch sc;
  const std::string rec = sc.write(
      "bad.vcd",
      "$timescale 1 us $end\n$var wire 1 a r_a $end\n$var wire 1 b r_b $end\n$var wire 1 c theta_a $end\n"
      "$var wire 1 d theta_b $end\n$enddefinitions $end\n"
      "#0\n0a\n0b\n0c\n0d\n"  // lines 7..11
      "#10\n1a\n"             // +1 radial at 10 us
      "#20\n1b\n"             // +1 at 20 us
      "#30\n0a\n0b\n"         // lines 16..18: 11 -> 00 at 30 us: illegal
      "#40\n1c\n"             // +1 angular at 40 us
      "#50\n");
  const std::string out = sc.path("bad.tape");
  const CliResult r = run_cli("capture " + rec + " --machine " + kMachine + " -o " + out + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("1 illegal transition (both"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("radial encoder at 3e-05 s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bad.vcd:18"), std::string::npos) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["illegal_transitions"]["total"], 1);
  EXPECT_EQ(j["illegal_transitions"]["radial"], 1);
  ASSERT_EQ(j["illegal_transitions"]["list"].size(), 1u);
  const json& t = j["illegal_transitions"]["list"][0];
  EXPECT_DOUBLE_EQ(t["t_s"].get<double>(), 30e-6);
  EXPECT_EQ(t["line"], 18);
  EXPECT_EQ(t["axis"], "radial");
  EXPECT_EQ(t["from"], "11");
  EXPECT_EQ(t["to"], "00");
  EXPECT_EQ(j["steps_total"], 3);
  const Tape got = read_tape(out);
  ASSERT_EQ(got.steps.size(), 3u);
  EXPECT_EQ(got.steps[2].axis, 1);
  EXPECT_EQ(got.steps[2].t_ns, 40000);
  // the summary lists it too
  const CliResult text = run_cli("capture " + rec + " --machine " + kMachine);
  EXPECT_NE(text.out.find("illegal    radial 11 -> 00 at 3e-05 s (line 18)"), std::string::npos) << text.out;
}

TEST(CliCapture, SignalsMappedByName) {
  Scratch sc;
  const std::string rec = sc.write("pv.csv",
                                   "; exported by a logic analyser\n"
                                   "time_s,D0,D1,D2,D3\n"
                                   "0.000000,0,0,0,0\n"
                                   "0.000100,0,1,0,0\n"   // radial 00 -> 01: down
                                   "0.000200,0,1,0,1\n"   // angular down
                                   "0.000300,0,1,1,1\n"); // angular 01 -> 11: down
  const json j = cli_json("capture " + rec + " --machine " + kMachine +
                          " --signals r_a=D0,r_b=D1,theta_a=D2,theta_b=D3 --start \"100 mm,1 rad\" --json");
  EXPECT_EQ(j["signals"]["theta_b"], "D3");
  EXPECT_EQ(j["counts"]["radial"]["minus"], 1);
  EXPECT_EQ(j["counts"]["angular"]["minus"], 2);
  EXPECT_DOUBLE_EQ(j["resolution_s"].get<double>(), 1e-6);
  // 100 mm at 0.001 in a step is node 3937 (3937.007...); 1 rad at 2 pi / 16000 is node 2546 (2546.47...)
  EXPECT_EQ(j["start_node"], json::array({3937, 2546}));
  EXPECT_EQ(j["end_node"], json::array({3936, 2544}));
}

TEST(CliCapture, BadRecordingsAreRefusedInOneLineNamingTheLine) {
  Scratch sc;
  const std::string out = sc.path("never.tape");
  const std::string head = "$timescale 1 ns $end\n$var wire 1 a r_a $end\n$var wire 1 b r_b $end\n"
                           "$var wire 1 c theta_a $end\n$var wire 1 d theta_b $end\n$enddefinitions $end\n";
  auto refused = [&](const std::string& name, const std::string& text, const std::string& args,
                     const std::string& mention) {
    SCOPED_TRACE(mention);
    const std::string rec = sc.write(name, text);
    expect_refused(run_cli("capture " + rec + " --machine " + kMachine + " -o " + out + " " + args), sc, out, mention);
  };
  refused("a.vcd", head + "#0\n0a\n0b\n0c\n0d\n#10\n1a\n#5\n1b\n", "", "a.vcd:14: time #5 goes back");
  refused("b.vcd", head, "--signals theta_b=enc_z", "b.vcd:6: no signal named 'enc_z'");
  refused("c.csv", "time_s,r_a,r_b,theta_a,theta_b\n0,0,0,0,0\n1e-3,1,0,0,0\n0.5e-3,1,1,0,0\n", "",
          "c.csv:4: time_s 0.5e-3 goes back");
  refused("d.csv", "time_s,r_a,r_b,theta_a\n0,0,0,0\n", "", "d.csv:1: no column 'theta_b'");
  refused("e.csv", "time_s,r_a,r_b,theta_a,theta_b\n0,0,0,0,x\n", "", "e.csv:2: 'x' is not a level 0 or 1");
  refused("f.dat", "hello\n", "", "f.dat: not a VCD file");
  refused("g.vcd", head + "#0\n0a\n0b\n0c\n0d\n", "--signals r_c=x", "--signals: unknown channel 'r_c'");
  refused("h.vcd", head + "#0\n0a\n0b\n0c\n0d\n", "--start \"1 m\"", "--start: give the start as R,THETA");
  refused("i.vcd", head + "#0\n0a\n0b\n0c\n", "", "i.vcd: no time at which all four channels");
  // a file that does not exist
  expect_refused(run_cli("capture " + sc.path("missing.vcd") + " --machine " + kMachine + " -o " + out), sc, out,
                 "missing.vcd: cannot be read");
}

// ---- step/dir ---------------------------------------------------------------------------------------------------

// The test's own model of a controller playing `steps` at speed scale 2 on a 4 us tick: each step fires on the
// tick nearest to its time / 2, `latency(i)` ns after the tick (an interrupt's), as a 2.4 us STEP pulse, with
// DIR set 1.5 us before when it changes; the `run` line rises at tick 0, which is t0_ns into the recording.
// Written as a VCD (10 ns timescale) with no capture code.
struct PinModel {
  int64_t tick_ns = 4000, t0_ns = 7000;
  int64_t latency(size_t i) const { return 200 + static_cast<int64_t>(i % 5) * 40; }
  int64_t tick_of(int64_t t_ns) const { return (t_ns + tick_ns) / (2 * tick_ns); }  // nearest to t / 2
  int64_t edge(size_t i, int64_t t_ns) const { return t0_ns + tick_of(t_ns) * tick_ns + latency(i); }
};

std::string step_dir_vcd(const std::vector<QStep>& steps, const PinModel& m, size_t skip = SIZE_MAX) {
  struct Ev {
    int64_t t;
    char id;
    int level;
  };
  std::vector<Ev> ev = {{0, '!', 0}, {0, '"', 0}, {0, '#', 0}, {0, '$', 0}, {0, '%', 0}, {m.t0_ns, '%', 1}};
  int dir[2] = {0, 0};
  for (size_t i = 0; i < steps.size(); ++i) {
    if (i == skip) continue;
    const QStep& s = steps[i];
    const int64_t e = m.edge(i, s.t_ns);
    const int want = s.dir > 0 ? 1 : 0;
    if (want != dir[s.axis]) ev.push_back({e - 1500, s.axis ? '$' : '"', want});
    dir[s.axis] = want;
    ev.push_back({e, s.axis ? '#' : '!', 1});
    ev.push_back({e + 2400, s.axis ? '#' : '!', 0});
  }
  std::stable_sort(ev.begin(), ev.end(), [](const Ev& a, const Ev& b) { return a.t < b.t; });
  std::string v =
      "$timescale 10 ns $end\n$scope module logic $end\n$var wire 1 ! r_step $end\n$var wire 1 \" r_dir $end\n"
      "$var wire 1 # theta_step $end\n$var wire 1 $ theta_dir $end\n$var wire 1 % run $end\n$upscope $end\n"
      "$enddefinitions $end\n$dumpvars\nx!\nx\"\nx#\nx$\nx%\n$end\n";
  int64_t now = -1;
  for (const Ev& e : ev) {
    char line[48];
    if (e.t != now) {
      std::snprintf(line, sizeof line, "#%lld\n", static_cast<long long>(e.t / 10));
      v += line;
    }
    now = e.t;
    std::snprintf(line, sizeof line, "%d%c\n", e.level, e.id);
    v += line;
  }
  char end[32];
  std::snprintf(end, sizeof end, "#%lld\n", static_cast<long long>(now / 10 + 100));
  return v + end;
}

// The limacon's tape in this test's scratch directory (limacon() keeps its steps for the whole process, its
// file only for the first test).
std::string limacon_tape(const Scratch& sc) {
  const std::string tape = sc.path("job.tape");
  const CliResult r = run_cli("digitize " + kSource + "/examples/limacon.toml -o " + tape);
  EXPECT_EQ(r.code, 0) << r.err;
  return tape;
}

TEST(CliCaptureStepDir, APlayRecordedAtTheStepPinsComparesWithItsTape) {
  Scratch sc;
  const Tape& src = limacon(sc);
  const std::string job = limacon_tape(sc);
  const PinModel m;
  const std::string rec = sc.write("pins.vcd", step_dir_vcd(src.steps, m));
  const std::string out = sc.path("pins.tape");
  const json j = cli_json("capture " + rec + " --encoding step-dir --origin run -o " + out + " --compare " + job +
                          " --speed-scale 2 --tick 4us --json");
  EXPECT_EQ(j["encoding"], "step-dir");
  EXPECT_EQ(j["signals"]["theta_dir"], "logic.theta_dir");
  EXPECT_EQ(j["origin_signal"], "logic.run");
  EXPECT_FALSE(j.contains("counts_per_step"));
  EXPECT_EQ(j["start_node"], json::array({src.start[0], src.start[1]}));  // the compared tape's start and grid
  EXPECT_EQ(j["end_node"], json::array({src.end[0], src.end[1]}));
  EXPECT_EQ(j["dir_setup_late"]["radial"], 0);  // 1.5 us before each edge
  // the model's errors, worked out here: each step's tick against its time / 2, and the latencies
  double worst = 0;
  int64_t jitter = 0;
  for (size_t i = 0; i < src.steps.size(); ++i) {
    worst = std::max(worst, std::abs(static_cast<double>(m.tick_of(src.steps[i].t_ns) * m.tick_ns) -
                                     static_cast<double>(src.steps[i].t_ns) / 2));
    jitter = std::max(jitter, m.latency(i));
  }
  const json& c = j["comparison"];
  EXPECT_EQ(c["result"], "PASS");
  EXPECT_EQ(c["steps_expected"], src.steps.size());
  EXPECT_EQ(c["steps_seen"], src.steps.size());
  EXPECT_EQ(c["mismatches"], 0);
  EXPECT_EQ(c["tolerance_ns"], 4000);
  EXPECT_DOUBLE_EQ(c["max_time_error_ns"].get<double>(), worst);
  EXPECT_DOUBLE_EQ(c["max_jitter_ns"].get<double>(), static_cast<double>(jitter));
  // the tape written: the steps at their edges' times from the run line's rise
  const Tape got = read_tape(out);
  ASSERT_EQ(got.steps.size(), src.steps.size());
  for (size_t i : {size_t{0}, src.steps.size() / 2, src.steps.size() - 1}) {
    EXPECT_EQ(got.steps[i].t_ns, m.edge(i, src.steps[i].t_ns) - m.t0_ns) << i;
    EXPECT_EQ(got.steps[i].axis, src.steps[i].axis);
    EXPECT_EQ(got.steps[i].dir, src.steps[i].dir);
  }
  // the summary says the same
  const CliResult text = run_cli("capture " + rec + " --encoding step-dir --origin run --compare " + job +
                                 " --speed-scale 2 --tick 4us");
  EXPECT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("0 mismatches"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find(": PASS"), std::string::npos) << text.out;
}

TEST(CliCaptureStepDir, AMissingPulseFailsTheComparisonWithExitStatus1) {
  Scratch sc;
  const Tape& src = limacon(sc);
  const std::string job = limacon_tape(sc);
  const size_t lost = 1000;
  const std::string rec = sc.write("lost.vcd", step_dir_vcd(src.steps, PinModel{}, lost));
  const CliResult r = run_cli("capture " + rec + " --encoding step-dir --origin run --compare " + job +
                              " --speed-scale 2 --tick 4us --json");
  EXPECT_EQ(r.code, 1) << r.err;
  const json c = json::parse(r.out)["comparison"];
  EXPECT_EQ(c["result"], "FAIL");
  EXPECT_EQ(c["steps_seen"], src.steps.size() - 1);
  EXPECT_GE(c["mismatches"].get<int>(), 1);
  ASSERT_GE(c["listed"].size(), 1u);
  EXPECT_EQ(c["listed"][0]["step"], lost + 1);  // the first place that differs is the lost step's
  // a polarity the wrong way round on the radial axis: its first step (radial, in the tape's direction) differs
  const std::string good = sc.write("good.vcd", step_dir_vcd(src.steps, PinModel{}));
  const CliResult inv = run_cli("capture " + good + " --encoding step-dir --origin run --invert-dir r --compare " +
                                job + " --speed-scale 2 --tick 4us --json");
  EXPECT_EQ(inv.code, 1) << inv.err;
  size_t first_radial = 0;
  while (src.steps[first_radial].axis != 0) ++first_radial;
  EXPECT_EQ(json::parse(inv.out)["comparison"]["listed"][0]["step"], first_radial + 1);
}

TEST(CliCaptureStepDir, OptionsThatDoNotApplyAndBadInput) {
  Scratch sc;
  const Tape& src = limacon(sc);
  const std::string rec = sc.write("pins.vcd", step_dir_vcd(src.steps, PinModel{}));
  const std::string out = sc.path("never.tape");
  // a machine file's counts_per_step does not apply to step/dir: said on stderr, one pulse is one step
  const std::string m4 =
      sc.write("m4.toml", replace(read_file(kMachine), "[machine]\n", "[machine]\ncounts_per_step = 4\n"));
  const CliResult note = run_cli("capture " + rec + " --encoding step-dir --machine " + m4 + " --json");
  ASSERT_EQ(note.code, 0) << note.err;
  EXPECT_NE(note.err.find("counts_per_step (4) does not apply to step/dir"), std::string::npos) << note.err;
  EXPECT_EQ(json::parse(note.out)["steps_total"], src.steps.size());
  auto refused = [&](const std::string& args, const std::string& mention) {
    SCOPED_TRACE(args);
    expect_refused(run_cli("capture " + rec + " -o " + out + " " + args), sc, out, mention);
  };
  refused("--machine " + kMachine + " --encoding stepdir", "--encoding: 'stepdir' is not an encoding");
  refused("--machine " + kMachine + " --encoding step-dir --signals r_a=D0", "give --encoding quadrature");
  refused("--machine " + kMachine + " --encoding step-dir --tick 4us", "--tick: applies with --compare");
  refused("--encoding step-dir", "--machine: give the machine file");
  refused("--machine " + kMachine + " --invert-dir r", "--invert-dir: applies to --encoding step-dir only");
  refused("--machine " + kMachine + " --dir-setup \"10 us\"", "--dir-setup: applies to --encoding step-dir only");
  refused("--machine " + kMachine + " --encoding step-dir --invert-dir x", "--invert-dir: 'x' is not r, theta");
  refused("--machine " + kMachine + " --encoding step-dir --origin enable", "no signal named 'enable'");
  refused("--encoding step-dir --compare " + sc.path("none.tape"), "none.tape");
}

}  // namespace

}  // namespace tu_cli_test_cli_capture
