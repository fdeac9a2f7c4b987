// End-to-end trust under bad input and interruptions: outputs named as the README shows them (plain file names),
// outputs that are devices, FIFOs or a full disk, missing directories, interrupted runs, and the exit statuses.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "tests/cli_runner.hpp"

extern char** environ;

namespace tu_cli_test_cli_robust {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
namespace fs = std::filesystem;

namespace {

const std::string kSmallCircle = cli_job("small_circle.toml");

// The scratch directory holds no temporary file.
void expect_no_partial(const Scratch& sc) {
  for (auto& e : fs::directory_iterator(sc.dir))
    EXPECT_EQ(e.path().string().find(".partial"), std::string::npos) << "left behind: " << e.path();
}

TEST(CliRobust, PlainOutputNamesAreWrittenInTheCurrentDirectory) {
  Scratch sc;
  sc.write("job.toml", kSmallCircle);
  CliResult r = run_cli("optimize job.toml --max-evaluations 40 --map-size 4 --map-image m.png --write-job best.toml",
                        sc.dir.string());
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(sc.path("best.toml")));
  ASSERT_TRUE(fs::exists(sc.path("m.png")));
  // the written job still finds its machine file (the relative path is rebased on the current directory)
  const std::string best = read_file(sc.path("best.toml"));
  EXPECT_NE(best.find("machines/fahim1983.toml"), std::string::npos) << best;
  r = run_cli("digitize best.toml --json", sc.dir.string());
  EXPECT_EQ(r.code, 0) << r.err;
  expect_no_partial(sc);
}

}  // namespace

namespace {

// Reads a FIFO while a command writes into it: opened without blocking before the command runs, drained until
// the command has ended and nothing is left.
struct FifoReader {
  std::string data;
  std::atomic<bool> done{false};
  std::thread th;
  explicit FifoReader(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK);
    th = std::thread([this, fd] {
      char buf[65536];
      for (;;) {
        const bool last = done.load();
        const ssize_t n = fd >= 0 ? ::read(fd, buf, sizeof buf) : 0;
        if (n > 0) {
          data.append(buf, static_cast<size_t>(n));
          continue;
        }
        if (last) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      if (fd >= 0) ::close(fd);
    });
  }
  std::string finish() {
    done.store(true);
    th.join();
    return data;
  }
};

bool is_fifo(const std::string& p) {
  struct stat st{};
  return ::lstat(p.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
}

// `cmd` run by the shell; its exit status (-1 when it did not exit).
int shell(const std::string& cmd) {
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

TEST(CliRobust, OutputIntoAFifoIsWrittenIntoIt) {
  Scratch sc;
  const std::string job = sc.write("job.toml", kSmallCircle), fifo = sc.path("tape.fifo"), tape = sc.path("a.tape");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  ASSERT_EQ(run_cli("digitize " + job + " -o " + tape).code, 0);
  FifoReader reader(fifo);
  const CliResult r = run_cli("digitize " + job + " -o " + fifo);
  const std::string got = reader.finish();
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(is_fifo(fifo)) << "the FIFO was replaced";
  EXPECT_TRUE(got == read_file(tape)) << "the FIFO carried " << got.size() << " bytes, not the tape";
  expect_no_partial(sc);

  // a text output (write_file_atomic) the same way
  ASSERT_EQ(run_cli("optimize " + job + " --max-evaluations 30 --map-size 3 --map " + sc.path("m.csv"), sc.dir.string()).code, 0);
  FifoReader csv_reader(fifo);
  const CliResult c = run_cli("optimize " + job + " --max-evaluations 30 --map-size 3 --map " + fifo);
  EXPECT_EQ(c.code, 0) << c.err;
  EXPECT_TRUE(is_fifo(fifo));
  EXPECT_EQ(csv_reader.finish(), read_file(sc.path("m.csv")));

  // an export (written as a stream) the same way
  ASSERT_EQ(run_cli("export " + job + " --format svg -o " + sc.path("p.svg")).code, 0);
  FifoReader svg_reader(fifo);
  const CliResult e = run_cli("export " + job + " --format svg -o " + fifo);
  EXPECT_EQ(e.code, 0) << e.err;
  EXPECT_TRUE(is_fifo(fifo));
  EXPECT_EQ(svg_reader.finish(), read_file(sc.path("p.svg")));
}

TEST(CliRobust, DevicesAreWrittenThroughNotReplaced) {
  Scratch sc;
  const std::string job = sc.write("job.toml", kSmallCircle);
  // links in the scratch directory: a program that replaced its output would replace the link, not the device
  const std::string null = sc.path("null"), full = sc.path("full");
  fs::create_symlink("/dev/null", null);
  fs::create_symlink("/dev/full", full);
  CliResult r = run_cli("digitize " + job + " -o " + null);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(null)) << "the output replaced the link to /dev/null";
  EXPECT_TRUE(fs::is_character_file(null));

  // a full disk: the tape, and a text output, are I/O errors (exit status 3) naming the output
  r = run_cli("digitize " + job + " -o " + full);
  expect_one_line_error(r, full, 3);
  EXPECT_TRUE(fs::is_symlink(full)) << "the output replaced the link to /dev/full";
  r = run_cli("optimize " + job + " --max-evaluations 30 --map-size 3 --map " + full);
  expect_one_line_error(r, full, 3);
  EXPECT_TRUE(fs::is_symlink(full));
  r = run_cli("export " + job + " --format svg -o " + full);  // written as a stream
  expect_one_line_error(r, full, 3);
  EXPECT_TRUE(fs::is_symlink(full));
  // two outputs, the second a full device: the device is written first, so its failure leaves the file output
  // as it was (here: not there)
  const std::string full_svg = sc.path("full.svg");
  fs::create_symlink("/dev/full", full_svg);
  r = run_cli("analyze " + std::string(POLARCAM_SOURCE_DIR) + "/examples/ch6/witch_grinding.toml --csv " +
              sc.path("a.csv") + " --plot " + full_svg);
  expect_one_line_error(r, full_svg, 3);
  EXPECT_FALSE(fs::exists(sc.path("a.csv")));
  expect_no_partial(sc);

  // the standard output as a file name (a link to the process's descriptor 1, as /dev/stdout is): the CSV goes to
  // the standard output, a regular file here, which is neither replaced nor truncated
  const std::string out = sc.path("out.txt"), stdout_link = sc.path("stdout");
  fs::create_symlink("/proc/self/fd/1", stdout_link);
  ASSERT_EQ(shell(std::string(POLARCAM_BIN) + " optimize " + job + " --max-evaluations 30 --map-size 3 --json --map " +
                  stdout_link + " > " + out + " 2>&1"),
            0)
      << read_file(out);
  EXPECT_TRUE(fs::is_symlink(stdout_link));
  EXPECT_NE(read_file(out).find("x_mm,y_mm"), std::string::npos) << read_file(out);
  EXPECT_NE(read_file(out).find("C_mm"), std::string::npos) << read_file(out);  // both the map and the JSON
}

TEST(CliRobust, AFullOrClosedStandardOutputIsAnIoError) {
  Scratch sc;
  const std::string job = sc.write("job.toml", kSmallCircle), err = sc.path("err.txt");
  EXPECT_EQ(shell(std::string(POLARCAM_BIN) + " digitize " + job + " --json > /dev/full 2>" + err), 3);
  EXPECT_NE(read_file(err).find("standard output"), std::string::npos) << read_file(err);
  // a reader that stops after ten bytes of a long listing
  const std::string tape = sc.path("lim.tape"), rc = sc.path("rc.txt");
  ASSERT_EQ(run_cli("digitize " + sc.write("lim.toml", cli_job("limacon.toml")) + " -o " + tape).code, 0);
  shell("( " + std::string(POLARCAM_BIN) + " inspect " + tape + " --csv 2>" + err + "; echo $? >" + rc +
        " ) | head -c 10 >/dev/null");
  EXPECT_EQ(read_file(rc), "3\n") << read_file(err);
  EXPECT_NE(read_file(err).find("standard output"), std::string::npos) << read_file(err);
}

TEST(CliRobust, MissingDirectoriesAndDirectoriesAsOutputsAreIoErrors) {
  Scratch sc;
  const std::string job = sc.write("job.toml", kSmallCircle), missing = sc.path("no-such-dir/out");
  expect_one_line_error(run_cli("digitize " + job + " -o " + missing + ".tape"), "no-such-dir", 3);
  expect_one_line_error(run_cli("digitize " + job + " -o " + sc.dir.string()), sc.dir.string(), 3);
  expect_one_line_error(run_cli("optimize " + job + " --max-evaluations 30 --map-size 3 --map " + missing + ".csv"),
                        "no-such-dir", 3);
  expect_one_line_error(run_cli("optimize " + job + " --write-job " + sc.path("machines")), "machines", 3);
  expect_one_line_error(run_cli("dda " + sc.write("dda.toml", cli_job("dda_circle.toml")) + " -o " + missing + ".tape"),
                        "no-such-dir", 3);
}

// A directory given where a file is read is bad input (exit status 2), named as one, whatever reads it: a job, a
// machine file the job names, a tape, a theta-rho pattern (which said "cannot read the pattern", exit status 3), a
// drawing. Found by a sweep of hostile inputs.
TEST(CliRobust, DirectoriesAsInputsAreBadInputNamedAsDirectories) {
  Scratch sc;
  const std::string dir = sc.path("inputs"), pattern = sc.path("pattern.thr");
  fs::create_directories(dir);
  fs::create_directories(pattern);
  const std::string machine = std::string(POLARCAM_SOURCE_DIR) + "/examples/machines/sand-table.toml";
  expect_one_line_error(run_cli("digitize " + dir), "is a directory", 2);
  expect_one_line_error(run_cli("inspect " + dir), "is a directory", 2);
  expect_one_line_error(run_cli("check " + pattern + " --machine " + machine + " --speed 40mm/s"), "is a directory", 2);
  expect_one_line_error(run_cli("digitize " + pattern + " --machine " + machine + " --speed 40mm/s"), "is a directory",
                        2);
  const std::string job = sc.write("job.toml", replace(kSmallCircle, "machines/fahim1983.toml", "inputs"));
  expect_one_line_error(run_cli("digitize " + job), "is a directory", 2);
}

// A damaged file's bytes quoted in an error line reach the terminal escaped: no control character, no malformed
// UTF-8 (a pattern of random bytes printed them raw).
TEST(CliRobust, ErrorLinesQuoteDamagedBytesEscaped) {
  Scratch sc;
  std::string junk = "\x1b[2J\x07\xff\xfe\x01 0.5\r\n";
  const std::string file = sc.write("junk.thr", junk);
  const std::string machine = std::string(POLARCAM_SOURCE_DIR) + "/examples/machines/sand-table.toml";
  const CliResult r = run_cli("check " + file + " --machine " + machine + " --speed 40mm/s");
  expect_one_line_error(r, "junk.thr:1", 2);
  for (size_t i = 0; i + 1 < r.err.size(); ++i) {
    const unsigned char b = static_cast<unsigned char>(r.err[i]);
    EXPECT_TRUE(b >= 0x20 && b < 0x7f) << "byte " << static_cast<int>(b) << " at " << i << " of " << r.err;
  }
  EXPECT_NE(r.err.find("\\x1b[2J\\x07\\xff\\xfe\\x01"), std::string::npos) << r.err;
}

// A long digitize (a grid 500 times finer than the examples'), interrupted by `sig` once its temporary tape exists:
// the process ends by that signal and leaves neither the temporary nor the tape.
void interrupt_digitize(int sig) {
  Scratch sc;
  std::string job = cli_job("limacon.toml");
  job = replace(job, "[machine]\n", "[machine]\nradial_resolution = \"0.0000005 in\"\nangular_steps_per_rev = 32000000\n");
  const std::string file = sc.write("big.toml", job), tape = sc.path("big.tape");
  const std::string cmd = "exec " + std::string(POLARCAM_BIN) + " digitize " + file + " -o " + tape + " >/dev/null";
  const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t dflt;
  sigemptyset(&dflt);
  sigaddset(&dflt, SIGINT);
  sigaddset(&dflt, SIGTERM);
  posix_spawnattr_setsigdefault(&attr, &dflt);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF);
  pid_t pid = -1;
  ASSERT_EQ(posix_spawn(&pid, "/bin/sh", nullptr, &attr, const_cast<char**>(argv), environ), 0);
  posix_spawnattr_destroy(&attr);
  auto partial = [&] {
    for (auto& e : fs::directory_iterator(sc.dir))
      if (e.path().string().find(".partial") != std::string::npos) return true;
    return false;
  };
  bool seen = false;
  for (int i = 0; i < 3000 && !seen; ++i) {  // until the temporary tape exists (the digitizing takes seconds)
    seen = partial();
    if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::kill(pid, sig);
  int st = 0;
  ASSERT_EQ(::waitpid(pid, &st, 0), pid);
  ASSERT_TRUE(seen) << "the temporary tape never appeared";
  EXPECT_TRUE(WIFSIGNALED(st) && WTERMSIG(st) == sig) << "status " << st;
  EXPECT_FALSE(partial()) << "the temporary tape was left behind";
  EXPECT_FALSE(fs::exists(tape));
}

TEST(CliRobust, InterruptedRunsLeaveNoTemporaryFiles) {
  interrupt_digitize(SIGINT);
  interrupt_digitize(SIGTERM);
}

}  // namespace

namespace {

const std::string kCh5Circle = std::string(POLARCAM_SOURCE_DIR) + "/examples/ch5/circle.toml";

// A command whose outputs are all refused when one of them is bad: no output written, nothing left behind.
TEST(CliRobust, EveryOptionIsCheckedBeforeAnyOutputIsWritten) {
  Scratch sc;
  const std::string csv = sc.path("s.csv"), map = sc.path("m.csv");
  expect_refused(run_cli("analyze " + kCh5Circle + " --csv " + csv + " --plot " + sc.path("ratios.jpg")), sc, csv,
                 "ratios.jpg");
  const std::string job = sc.write("job.toml", kSmallCircle);
  CliResult r = run_cli("optimize " + job + " --max-evaluations 30 --map-size 3 --map " + map + " --map-image " +
                        sc.path("no-such-dir/m.png"));
  expect_one_line_error(r, "no-such-dir", 3);
  EXPECT_FALSE(fs::exists(map));
  r = run_cli("optimize " + job + " --max-evaluations 30 --map-size 3 --map " + map + " --write-job " +
              sc.path("no-such-dir/best.toml"));
  expect_one_line_error(r, "no-such-dir", 3);
  EXPECT_FALSE(fs::exists(map));
  r = run_cli("analyze " + kCh5Circle + " --plot " + sc.path("p.png") + " --csv " + sc.path("no-such-dir/s.csv"));
  expect_one_line_error(r, "no-such-dir", 3);
  EXPECT_FALSE(fs::exists(sc.path("p.png")));
  expect_no_partial(sc);
}

// 0 GO, 1 NO-GO, 2 bad input, 3 I/O, 4 internal: in every command's help, and `report` exits 1 on NO-GO.
TEST(CliRobust, ExitStatusesAreDocumentedAndReportSaysNoGo) {
  for (const char* cmd : {"digitize", "inspect", "dda", "play", "controller-sim", "error", "optimize", "analyze",
                          "motor", "compare", "capacity", "report"}) {
    const CliResult h = run_cli(std::string(cmd) + " --help");
    EXPECT_EQ(h.code, 0) << cmd;
    for (const char* words : {"Exit status", "0 success", "1 computed but NO-GO", "2 bad input or usage",
                              "3 I/O or device", "4 internal error"})
      EXPECT_NE(h.out.find(words), std::string::npos) << cmd << " --help lacks \"" << words << "\"";
  }
  Scratch sc;
  // the circle ground at Table 6.2's conditions needs more torque than its motors give: NO-GO
  const std::string ch6 = std::string(POLARCAM_SOURCE_DIR) + "/examples/ch6/circle_grinding.toml";
  const CliResult a = run_cli("analyze " + ch6);
  ASSERT_EQ(a.code, 1) << "the example is not NO-GO any more: " << a.out;
  const CliResult r = run_cli("report " + ch6 + " -o " + sc.path("r.html") + " --map-size 4 --max-evaluations 20");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.out.find("NO-GO"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(sc.path("r.html")));  // the report is written all the same: it says what to change
}

}  // namespace

}  // namespace tu_cli_test_cli_robust
