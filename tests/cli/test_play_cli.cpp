// `polarcam play` and `polarcam controller-sim` end to end over real pseudo-terminals: the emulator's log
// against the tape, faults, and bad input refused before any step is sent. Every emulator started here is
// killed and reaped by the test.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <iterator>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "tests/cli_runner.hpp"
#include "tests/example_tapes.hpp"
#include "tests/tape_log.hpp"

extern char** environ;

namespace polarcam {
namespace tu_cli_test_play_cli {  // named: the test files compile together

using test::example_tape;
using test::run_cli;
using test::Scratch;

// A running `polarcam controller-sim`, stopped and reaped on destruction.
struct Emulator {
  pid_t pid = -1;
  std::string pty, log, out;
  Emulator(const Scratch& s, const std::string& args) {
    log = s.path("emulator.csv");
    out = s.path("emulator.out");
    const std::string cmd = std::string(POLARCAM_BIN) + " controller-sim --pty --log " + log +
                            " --exit-after-idle 60 " + args + " >" + out + " 2>" + s.path("emulator.err");
    const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
    // exec replaces the shell, so the pid is the emulator's
    const std::string exec_cmd = "exec " + cmd;
    argv[2] = exec_cmd.c_str();
    if (posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) != 0) pid = -1;
    for (int i = 0; i < 500 && pty.empty(); ++i) {  // up to 5 s for the first line
      std::ifstream in(out);
      std::getline(in, pty);
      if (pty.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  ~Emulator() {
    if (pid > 0) {
      ::kill(pid, SIGTERM);
      int st = 0;
      for (int i = 0; i < 300; ++i) {  // 3 s, then SIGKILL
        if (::waitpid(pid, &st, WNOHANG) == pid) return;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &st, 0);
    }
  }
  std::vector<std::string> lines() const {
    std::ifstream in(log);
    std::vector<std::string> v;
    std::string l;
    while (std::getline(in, l)) v.push_back(l);
    return v;
  }
};

// The emulator's CSV (a header, then t_ns,r|theta,+1|-1 per step) against the tape read independently: step for step,
// within one 1 us tick of t / K.
void expect_log_is_tape(const std::vector<std::string>& lines, const std::string& tape, int64_t K) {
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0], "t_ns,axis,dir");
  std::vector<test::LoggedStep> log;
  for (size_t i = 1; i < lines.size(); ++i) {
    std::istringstream ls(lines[i]);
    std::string ts, axis, dir;
    std::getline(ls, ts, ',');
    std::getline(ls, axis, ',');
    std::getline(ls, dir, ',');
    ASSERT_TRUE((axis == "r" || axis == "theta") && (dir == "+1" || dir == "-1")) << "step " << i << ": " << lines[i];
    log.push_back({std::stoull(ts), axis == "r" ? 0 : 1, dir == "+1" ? 1 : -1});
  }
  test::expect_log_follows_tape(tape, K, log);
}

// Example `name` played at ten times speed to an emulator with `faults`: its JSON summary in `j`, and the
// emulator's log against the tape.
void play_at_ten_times_speed(const std::string& name, const std::string& faults, nlohmann::json& j) {
  Scratch s;
  const std::string tape = example_tape(name);
  Emulator emu(s, faults);
  ASSERT_FALSE(emu.pty.empty());
  j = test::cli_json("play " + tape + " --port " + emu.pty + " --speed-scale 10 --json");
  expect_log_is_tape(emu.lines(), tape, 10);
}

TEST(PlayCli, LimaconAtTenTimesSpeedOverAPtyWithDroppedBytes) {
  nlohmann::json j;
  play_at_ten_times_speed("limacon", "--faults drop=0.01,seed=3", j);
  EXPECT_EQ(j["steps_confirmed"], 22000);
  EXPECT_EQ(j["steps_sent"], 22000);
  EXPECT_EQ(j["underruns"], 0);
  for (const char* k : {"retransmissions", "duration_s"}) EXPECT_TRUE(j.contains(k)) << k;
  // the limits the emulator reports at IDENTIFY (protocol version 4): 4096 items; one step per axis per 1 us tick
  EXPECT_EQ(j["controller_slots"], 4096);
  EXPECT_EQ(j["controller_max_step_rate"], 2 * 1000000);
}

// An emulator as small as the reference firmware (384 bytes of queue, no frame kept after a missing one): the
// credits in bytes keep the host within its queue (it faults with "queue overflow" otherwise) and nothing is sent
// twice on a clean line.
TEST(PlayCli, LimaconToAControllerOf384BytesThatDropsFramesAhead) {
  nlohmann::json j;
  play_at_ten_times_speed("limacon", "--queue-bytes 384 --drop-ahead", j);
  EXPECT_EQ(j["steps_confirmed"], 22000);
  EXPECT_EQ(j["underruns"], 0);
  EXPECT_EQ(j["retransmissions"], 0);
  EXPECT_EQ(j["naks"], 0);
}

// One controller, several jobs: each `play` numbers its requests from 1, and the controller forgets the earlier
// host's at IDENTIFY, so the second job is configured and played rather than taken for a repeat of the first (it
// failed with "malformed queue item" and left the controller faulted). The limacon (22 000 steps), then the
// circle, then the limacon again, each to its last step; a job the controller refuses is refused again, not
// "not configured".
TEST(PlayCli, OneControllerPlaysSeveralTapesInARow) {
  Scratch s;
  Emulator emu(s, "--time-scale 50");
  ASSERT_FALSE(emu.pty.empty());
  const std::string limacon = example_tape("limacon"), circle = example_tape("circle");
  for (const std::string& tape : {limacon, circle, limacon}) {
    SCOPED_TRACE(tape);
    const nlohmann::json j = test::cli_json("play " + tape + " --port " + emu.pty + " --speed-scale 10 --json");
    EXPECT_EQ(j["steps_confirmed"], j["steps_sent"]);
    if (tape == limacon) {
      EXPECT_EQ(j["steps_confirmed"], 22000);
    }
  }
  Scratch s2;
  const std::string other = s2.write("other.toml", "[machine]\nradial_resolution = \"0.0005 in\"\nangular_steps_per_rev = 16000\n");
  Emulator strict(s2, "--machine " + other);
  ASSERT_FALSE(strict.pty.empty());
  for (int i = 0; i < 2; ++i)
    expect_one_line_error(run_cli("play " + circle + " --port " + strict.pty), "grid mismatch");
}

// A sand-table arm's tape (the example table: 2 560 radial steps of coupling a turn of the arm, 20 000 angular
// steps a turn): its radial index is the radial motor's, r + c theta, which runs far past r_max while the ball stays
// within the 200 mm table. The work area bounds the ball, so the tape plays; scaling the radial motor or turning
// the arm would distort the drawing on such an arm, and is refused.
TEST(PlayCli, ASandTableTapePlaysAndIsNotScaledOrTurned) {
  Scratch s;
  const std::string src = POLARCAM_SOURCE_DIR;
  const std::string tape = s.path("rose.tape");
  ASSERT_EQ(run_cli("digitize " + src + "/examples/patterns/rose.thr --machine " + src +
                    "/examples/machines/sand-table.toml --speed \"40 mm/s\" -o " + tape)
                .code,
            0);
  const nlohmann::json j = test::cli_json("play " + tape + " --simulate --json");
  EXPECT_GT(j["steps_total"].get<uint64_t>(), 0u);
  EXPECT_EQ(j["steps_executed"], j["steps_total"]);
  EXPECT_EQ(j["steps_mismatched"], 0);
  EXPECT_EQ(j["end_node"], j["end_node_expected"]);
  expect_one_line_error(run_cli("play " + tape + " --simulate --size-scale 1/2"), "--size-scale: scales the radial motor");
  expect_one_line_error(run_cli("play " + tape + " --simulate --angle-offset 100"), "--angle-offset: turns the arm");
}

TEST(PlayCli, SerpentineAtTenTimesSpeedWithCorruptedBytes) {
  nlohmann::json j;
  play_at_ten_times_speed("serpentine", "--faults corrupt=0.01,seed=5", j);
  EXPECT_EQ(j["underruns"], 0);
}

TEST(PlayCli, BadInputIsRefusedBeforeAnyStep) {
  Scratch s;
  const std::string tape = example_tape("circle");
  Emulator emu(s, "");
  ASSERT_FALSE(emu.pty.empty());
  auto refused = [&](const std::string& args, const std::string& words, int code = 2) {
    SCOPED_TRACE(args);
    expect_one_line_error(run_cli("play " + args), words, code);
  };
  refused(tape + " --port /dev/polarcam-no-such-port", "cannot open serial port /dev/polarcam-no-such-port", 3);
  refused(tape + " --port " + emu.pty + " --baud 12345", "--baud 12345");
  refused(tape + " --port " + emu.pty + " --baud 9600", "no answer", 3);
  refused(tape + " --port " + emu.pty + " --size-scale 2/1", "r_max");
  refused(tape + " --port " + emu.pty + " --speed-scale 0", "--speed-scale");
  refused(tape + " --port " + emu.pty + " --speed-scale 1e300", "--speed-scale '1e300': expected a positive decimal number, or a ratio of two");
  refused(tape + " --port " + emu.pty + " --accel 0", "--accel: '0' is a plain number, expected an acceleration");
  refused(tape + " --port " + emu.pty + " --accel \"0 m/s^2\"", "--accel: must be a positive acceleration");
  const std::string other = s.write("other.toml", "[machine]\nradial_resolution = \"0.0005 in\"\nangular_steps_per_rev = 16000\n");
  refused(tape + " --port " + emu.pty + " --machine " + other, "another machine grid");
  // the circle's 21 s at 1/10^7 would be 2.1e8 s, beyond the 2^47 ticks (1.41e8 s of 1 us) a controller's clock
  // times: refused by name instead of an internal error at the end of the simulation
  refused(tape + " --simulate --speed-scale 1/10000000",
          "--speed-scale: at speed scale 1/10000000 the playback would last more than 1.41e+08 s");
  // the line's options go with --port, the simulated controller's with --simulate; numbers that would wrap
  refused(tape + " --simulate --baud 9600", "--baud requires --port");
  refused(tape + " --simulate --flow hardware", "--flow requires --port");
  refused(tape + " --port " + emu.pty + " --tick 333", "--tick requires --simulate");
  refused(tape + " --port " + emu.pty + " --log " + s.path("never.csv"), "--log requires --simulate");
  refused(tape + " --simulate --resume -1", "--resume");
  refused(tape + " --simulate --angle-offset 9223372036854775807", "--angle-offset");
  refused(tape + " --simulate --log ''", "the output file name is empty", 3);
  refused(tape + " --simulate --machine " + tape, "is a step tape, not a machine file");
  refused(tape + " --simulate --speed-scale 1/0", "--speed-scale '1/0': has a zero denominator");
  refused(s.write("junk.tape", "not a tape") + " --port " + emu.pty, "junk.tape");
  // ports that are not serial ports: a device error (exit status 3), one line, never an abort
  const std::string fifo = s.path("port.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& port : {tape, std::string("/dev/null"), fifo}) refused(tape + " --port " + port, "is not a serial port", 3);
  EXPECT_EQ(emu.lines().size(), 1u);  // the header only: not one step executed
}

TEST(PlayCli, ControllerResetStopsWithAClearMessage) {
  Scratch s;
  const std::string tape = example_tape("witch");
  Emulator emu(s, "--faults reset@1.5");
  ASSERT_FALSE(emu.pty.empty());
  auto r = run_cli("play " + tape + " --port " + emu.pty + " --speed-scale 10 --json");
  EXPECT_EQ(r.code, 3) << r.err;  // a device error
  EXPECT_NE(r.err.find("reset"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("re-home"), std::string::npos) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["completed"], false);
  EXPECT_GT(j["steps_confirmed"].get<int>(), 0);
  EXPECT_LT(j["steps_confirmed"].get<int>(), j["steps_total"].get<int>());
}

// The steps of two controllers' logs (header lines dropped), one after the other, against the tape's records: every
// step once, in order.
void expect_logs_are_the_tape_once(const std::vector<std::string>& first, const std::vector<std::string>& second,
                                   const std::string& tape) {
  std::vector<std::string> steps;
  for (const auto* log : {&first, &second})
    for (size_t i = 1; i < log->size(); ++i) steps.push_back((*log)[i].substr((*log)[i].find(',') + 1));
  TapeReader rd(tape);
  StepRecord r;
  size_t i = 0;
  while (rd.next(r)) {
    ASSERT_LT(i, steps.size()) << "the logs end after " << steps.size() << " steps";
    ASSERT_EQ(steps[i], std::string(r.axis == 0 ? "r" : "theta") + (r.dir > 0 ? ",+1" : ",-1")) << "step " << i + 1;
    ++i;
  }
  EXPECT_EQ(i, steps.size()) << "the logs have more steps than the tape";
}

// The N of "--resume N" in a message.
uint64_t resume_step(const std::string& message) {
  const auto p = message.find("--resume ");
  return p == std::string::npos ? 0 : std::stoull(message.substr(p + 9));
}

TEST(PlayCli, AControllerThatDiesIsResumedWithNoStepLostOrRepeated) {
  Scratch s1, s2;
  const std::string tape = example_tape("witch");
  std::vector<std::string> first;
  uint64_t n = 0;
  {
    Emulator emu(s1, "");
    ASSERT_FALSE(emu.pty.empty());
    test::CliResult r;
    std::thread play([&] { r = run_cli("play " + tape + " --port " + emu.pty + " --speed-scale 5"); });
    for (int i = 0; i < 3000 && emu.lines().size() < 1500; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ::kill(emu.pid, SIGTERM);  // the controller dies mid-stream
    int st = 0;
    ::waitpid(emu.pid, &st, 0);
    emu.pid = -1;
    play.join();
    expect_one_line_error(r, "--resume ", 3);
    first = emu.lines();
    n = resume_step(r.err);
    EXPECT_EQ(n + 1, first.size()) << "the step offered is not the last one executed: " << r.err;
    ASSERT_GT(n, 0u);
  }
  Emulator again(s2, "");  // restarted (on a new pseudo-terminal)
  ASSERT_FALSE(again.pty.empty());
  const nlohmann::json j =
      test::cli_json("play " + tape + " --port " + again.pty + " --speed-scale 5 --resume " + std::to_string(n) + " --json");
  EXPECT_EQ(j["completed"], true);
  EXPECT_EQ(j["step_reached"].get<uint64_t>(), n + j["steps_confirmed"].get<uint64_t>());
  expect_logs_are_the_tape_once(first, again.lines(), tape);
}

TEST(PlayCli, ResumingTheSimulatedMachineGivesTheRestOfTheTape) {
  Scratch s;
  const std::string tape = example_tape("serpentine");
  auto run = [&](const std::string& extra, const std::string& log) {
    auto r = run_cli("play " + tape + " --simulate --json --log " + s.path(log) + extra);
    EXPECT_EQ(r.code, 0) << r.err;
    std::ifstream in(s.path(log));
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
  };
  const std::vector<std::string> head = run("", "all.csv");
  ASSERT_GT(head.size(), 1001u);
  const std::vector<std::string> first(head.begin(), head.begin() + 1001);  // the header and 1000 steps
  expect_logs_are_the_tape_once(first, run(" --resume 1000", "rest.csv"), tape);
  expect_one_line_error(run_cli("play " + tape + " --simulate --resume " + std::to_string(head.size() - 1)),
                        "--resume");
}

TEST(PlayCli, SimulatedMachineReportsTheExecutedPath) {
  Scratch s;
  const std::string tape = example_tape("serpentine");
  auto r = run_cli("play " + tape + " --simulate --speed-scale 2 --json --log " + s.path("sim.csv"));
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["steps_mismatched"], 0);
  EXPECT_LE(j["max_time_error_ns"].get<double>(), 1000.0);
  EXPECT_EQ(j["steps_executed"], j["steps_total"]);
  std::ifstream in(s.path("sim.csv"));
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  expect_log_is_tape(lines, tape, 2);
}

TEST(PlayCli, EmulatorRefusesBadFaultSpecs) {
  Scratch s;
  auto r = run_cli("controller-sim --pty --log " + s.path("x.csv") + " --faults drop=5");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("drop"), std::string::npos) << r.err;
}

// A log that cannot be written is an I/O error (exit status 3) naming it: one that cannot be created or written at
// all before the emulator starts, and one whose writes start failing while steps run (a file size limit: the writes
// beyond it fail with EFBIG), where the emulator stops and the player, its controller gone, stops too.
TEST(PlayCli, AnEmulatorLogThatCannotBeWrittenIsAnIoError) {
  Scratch s;
  for (const std::string& log : {s.path("no-such-dir/x.csv"), std::string(s.dir), std::string("/dev/full")}) {
    SCOPED_TRACE(log);
    const auto r = run_cli("controller-sim --pty --log " + log + " --exit-after-idle 1");
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_NE(r.err.find(log), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  const std::string log = s.path("small.csv"), out = s.path("emu.out"), err = s.path("emu.err"), rc = s.path("emu.rc");
  // ulimit -f counts blocks of 512 bytes in sh: the log may hold 2048 bytes, some 80 steps of the limacon's 22 000
  const std::string cmd = "(trap '' XFSZ; ulimit -f 4; " + std::string(POLARCAM_BIN) + " controller-sim --pty --log " +
                          log + " --exit-after-idle 30 >" + out + " 2>" + err + "; echo $? >" + rc + ") &";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::string pty;
  for (int i = 0; i < 500 && pty.empty(); ++i) {
    std::ifstream in(out);
    std::getline(in, pty);
    if (pty.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_FALSE(pty.empty());
  const auto p = run_cli("play " + example_tape("limacon") + " --port " + pty + " --speed-scale 10");
  EXPECT_EQ(p.code, 3) << p.err;
  std::string code;
  for (int i = 0; i < 1000 && code.empty(); ++i) {
    std::ifstream in(rc);
    std::getline(in, code);
    if (code.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(code, "3");
  std::ifstream e(err);
  const std::string message((std::istreambuf_iterator<char>(e)), {});
  EXPECT_NE(message.find(log), std::string::npos) << message;
  EXPECT_NE(message.find("could not be written"), std::string::npos) << message;
}

// ------------------------------------------------------------------------------------------- tool events

using test::CliResult;

const std::string kSrc = std::string(POLARCAM_SOURCE_DIR);
const std::string kPlotter = kSrc + "/examples/machines/pen-plotter.toml";
const std::string kLogoJob = kSrc + "/examples/patterns/logo.svg --machine " + kPlotter + " --speed \"20 mm/s\"";

struct Row {
  uint64_t t_ns;
  std::string what, dir;  // r/theta and +1/-1, or tool and up/down
};

std::vector<Row> rows(const std::vector<std::string>& lines) {
  std::vector<Row> v;
  for (size_t i = 1; i < lines.size(); ++i) {
    std::istringstream ls(lines[i]);
    std::string t, a, d;
    std::getline(ls, t, ',');
    std::getline(ls, a, ',');
    std::getline(ls, d, ',');
    v.push_back({std::stoull(t), a, d});
  }
  return v;
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> v;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

// The pen plotter's drawing of the logo (four contours, three rapids with the pen up) digitized and played at
// speed scale K to the emulator: its log holds first the pen's state (down), then every step and every tool event
// of the tape's own listing (inspect --csv) in order, each within one 1 us tick of its tape time divided by K plus
// the machine file's tool_dwell (0.2 s) for every tool event before it.
TEST(PlayCli, PenPlotterTapeToTheEmulatorStepsAndLiftsInOrderAndOnTime) {
  Scratch s;
  const std::string tape = s.path("logo.tape");
  ASSERT_EQ(run_cli("digitize " + kLogoJob + " -o " + tape).code, 0);
  const CliResult listing = run_cli("inspect " + tape + " --csv");
  ASSERT_EQ(listing.code, 0) << listing.err;
  const std::vector<Row> want = rows(split_lines(listing.out));
  const int64_t K = 10;
  const double dwell_ns = 0.2e9;
  Emulator emu(s, "--faults drop=0.005,seed=4");
  ASSERT_FALSE(emu.pty.empty());
  const auto j = test::cli_json("play " + tape + " --port " + emu.pty + " --speed-scale " + std::to_string(K) + " --json");
  EXPECT_EQ(j["tool_events"], 7);  // the pen's state at the start, then the tape's six events
  EXPECT_EQ(j["completed"], true);
  const std::vector<std::string> lines = emu.lines();
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0], "t_ns,axis,dir");
  const std::vector<Row> got = rows(lines);
  ASSERT_EQ(got.size(), want.size() + 1);
  EXPECT_EQ(got[0].what, "tool");
  EXPECT_EQ(got[0].dir, "down");
  EXPECT_LE(got[0].t_ns, 1000u);
  size_t events = 1, tool_rows = 0;
  for (size_t i = 0; i < want.size(); ++i) {
    const Row& g = got[i + 1];
    ASSERT_EQ(g.what, want[i].what) << "row " << i + 1;
    ASSERT_EQ(g.dir, want[i].dir) << "row " << i + 1;
    const double exact = static_cast<double>(want[i].t_ns) / static_cast<double>(K) + static_cast<double>(events) * dwell_ns;
    EXPECT_LE(std::fabs(static_cast<double>(g.t_ns) - exact), 1000.0) << "row " << i + 1 << ": " << g.what;
    if (g.what == "tool") ++events, ++tool_rows;
  }
  EXPECT_EQ(tool_rows, 6u);
  // the simulated machine plays the same tape with the same tool items
  const auto sim = test::cli_json("play " + tape + " --simulate --speed-scale 10 --json");
  EXPECT_EQ(sim["tool_events"], 7);
  EXPECT_EQ(sim["tool_events_executed"], 7);
  EXPECT_EQ(sim["tool_events_mismatched"], 0);
  EXPECT_EQ(sim["steps_mismatched"], 0);
  EXPECT_LE(sim["max_tool_time_error_ns"].get<double>(), 1000.0);
  EXPECT_LE(sim["max_time_error_ns"].get<double>(), 1000.0);
  EXPECT_EQ(sim["tool_dwell_s"], 0.2);
}

// A controller that drives no tool: the lifting tape is refused in one line naming the tape before any step.
TEST(PlayCli, ControllerWithoutAToolRefusesTheLiftingTape) {
  Scratch s;
  const std::string tape = s.path("logo.tape");
  ASSERT_EQ(run_cli("digitize " + kLogoJob + " -o " + tape).code, 0);
  Emulator emu(s, "--no-tool");
  ASSERT_FALSE(emu.pty.empty());
  const CliResult r = run_cli("play " + tape + " --port " + emu.pty);
  expect_one_line_error(r, "drives no tool");
  EXPECT_NE(r.err.find("logo.tape"), std::string::npos) << r.err;
  EXPECT_EQ(emu.lines(), std::vector<std::string>{"t_ns,axis,dir"});
}

}  // namespace tu_cli_test_play_cli
}  // namespace polarcam
