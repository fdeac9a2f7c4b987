// End-to-end trust under bad input and interruptions: outputs named as the README shows them (plain file names),
// outputs that are devices, FIFOs or a full disk, missing directories, interrupted runs, and the exit statuses.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "tests/cli_runner.hpp"

extern char** environ;

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
