// Progress on the terminal: a bar with the percentage and an ETA on stderr when stderr is a terminal (here a
// pseudo-terminal made by script(1)), nothing when it is a pipe or a file, nothing with --quiet.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_progress {  // the test files of a program compile together (unity build)

using namespace polarcam::test;

namespace {

// The thesis's circle on a grid ten times finer (about 10^5 steps): long enough for the bar to be drawn.
std::string fine_job(const Scratch& sc) {
  std::filesystem::create_directories(sc.dir / "ch5");
  // (the scratch directory has the machine file at machines/, as examples/ does)
  std::string text = read_file(std::string(POLARCAM_SOURCE_DIR) + "/examples/ch5/circle.toml");
  const std::string m = "[machine]\n";
  text.replace(text.find(m), m.size(), m + "radial_resolution = \"0.0001 in\"\nangular_steps_per_rev = 160000\n");
  return sc.write("ch5/fine.toml", text);
}

// What the command wrote on its terminal (stdout goes to a file): script(1) runs it on a pseudo-terminal.
std::string on_a_terminal(const std::string& args, const Scratch& sc) {
  const std::string log = sc.path("pty.log");
  const std::string cmd = "script -qec \"" + std::string(POLARCAM_BIN) + " " + args + " > " + sc.path("stdout.txt") +
                          "\" /dev/null > " + log + " 2>&1 < /dev/null";
  const int st = std::system(cmd.c_str());
  EXPECT_EQ(st, 0) << cmd;
  return read_file(log);
}

}  // namespace

TEST(Progress, ErrorDrawsABarOnATerminalOnly) {
  if (std::system("command -v script > /dev/null 2>&1") != 0) GTEST_SKIP() << "script(1) is not installed";
  Scratch sc;
  const std::string job = fine_job(sc), tape = sc.path("fine.tape");
  ASSERT_EQ(run_cli("digitize " + job + " -o " + tape).code, 0);
  const std::string args = "error " + tape + " --job " + job;

  const std::string tty = on_a_terminal(args, sc);
  EXPECT_NE(tty.find('%'), std::string::npos) << tty;
  EXPECT_NE(tty.find("ETA"), std::string::npos) << tty;
  EXPECT_NE(tty.find("\r\033[K"), std::string::npos) << "the bar is erased at the end: " << tty;
  EXPECT_NE(read_file(sc.path("stdout.txt")).find("area"), std::string::npos);  // the result, on stdout

  const CliResult piped = run_cli(args);
  EXPECT_EQ(piped.code, 0) << piped.err;
  EXPECT_EQ(piped.err, "");

  EXPECT_EQ(on_a_terminal(args + " --quiet", sc), "");
}

TEST(Progress, DigitizeDrawsABarOnATerminalOnly) {
  if (std::system("command -v script > /dev/null 2>&1") != 0) GTEST_SKIP() << "script(1) is not installed";
  Scratch sc;
  const std::string job = fine_job(sc), tape = sc.path("fine.tape");
  const std::string args = "digitize " + job + " -o " + tape;
  // the bar is drawn at the first report (4096 steps in), so even a fast run shows it on a terminal
  const std::string tty = on_a_terminal(args, sc);
  EXPECT_NE(tty.find("digitize ["), std::string::npos) << tty;
  EXPECT_NE(tty.find('%'), std::string::npos) << tty;
  EXPECT_NE(tty.find("\r\033[K"), std::string::npos) << "the bar is erased at the end: " << tty;
  EXPECT_NE(read_file(sc.path("stdout.txt")).find("steps"), std::string::npos);  // the summary, on stdout
  const std::string quiet = on_a_terminal(args + " --quiet", sc);
  EXPECT_EQ(quiet.find('%'), std::string::npos) << quiet;
}

// check on a machine steps the whole pattern: 40 turns of the example sand table, some 800 000 angular steps
TEST(Progress, CheckOnAMachineDrawsABarOnATerminalOnly) {
  if (std::system("command -v script > /dev/null 2>&1") != 0) GTEST_SKIP() << "script(1) is not installed";
  Scratch sc;
  const std::string thr = sc.write("turns.thr", "0 0.2\n251.32741228718345 0.9\n");
  const std::string args = "check " + thr + " --machine " + std::string(POLARCAM_SOURCE_DIR) +
                           "/examples/machines/sand-table.toml --speed 40mm/s";  // no quotes: script(1) quotes the command
  const std::string tty = on_a_terminal(args, sc);
  EXPECT_NE(tty.find("check ["), std::string::npos) << tty;
  EXPECT_NE(tty.find("\r\033[K"), std::string::npos) << "the bar is erased at the end: " << tty;
  EXPECT_NE(read_file(sc.path("stdout.txt")).find("on machine"), std::string::npos);  // the findings, on stdout
  EXPECT_EQ(on_a_terminal(args + " --quiet", sc).find('%'), std::string::npos);
  const CliResult piped = run_cli(args);
  EXPECT_EQ(piped.code, 0) << piped.err;
  EXPECT_EQ(piped.err, "");
}

// Every command that may run for seconds prints nothing on stderr when stderr is not a terminal (its result on
// stdout, its files written); --quiet is accepted and changes nothing there. The three searches (seconds each
// under the sanitizers) run once; the rest with and without --quiet.
TEST(Progress, LongCommandsAreSilentWhenPiped) {
  Scratch sc;
  const std::string ex = std::string(POLARCAM_SOURCE_DIR) + "/examples/";
  const std::string table = ex + "machines/sand-table.toml";
  struct Command {
    std::string args;
    bool also_quiet;
  };
  const std::vector<Command> commands = {
      {"digitize " + ex + "limacon.toml -o " + sc.path("l.tape"), true},
      {"optimize " + ex + "limacon.toml --max-evaluations 30 --map " + sc.path("m.csv") + " --map-size 5 --json", false},
      {"optimize " + ex + "ch6/circle_inertial.toml --objective pareto --survey 4 --levels 1 --max-evaluations 20 --json --quiet",
       false},
      {"report " + ex + "ch6/circle_inertial.toml -o " + sc.path("r.html") + " --map-size 4 --max-evaluations 20", false},
      {"export " + ex + "patterns/star.thr --machine " + table + " --format thr -o " + sc.path("s.thr"),
       true},
      {"analyze " + ex + "ch5/circle.toml --json", true},
      {"compare " + ex + "testpiece_diamond.toml --json", true},
  };
  for (const Command& c : commands)
    for (const char* extra : {"", " --quiet"}) {
      if (*extra && !c.also_quiet) continue;
      const CliResult r = run_cli(c.args + extra);
      EXPECT_TRUE(r.code == 0 || r.code == 1) << c.args << extra << ": " << r.err;  // 1: a NO-GO verdict
      EXPECT_EQ(r.err, "") << c.args << extra;
      EXPECT_FALSE(r.out.empty()) << c.args << extra;
    }
}

}  // namespace tu_cli_test_cli_progress
