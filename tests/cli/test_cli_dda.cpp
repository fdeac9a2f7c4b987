// End-to-end tests of `polarcam dda`: the JSON summary, the Cartesian tape as `inspect` reads it, the examples,
// determinism, and bad input (one line naming the file and key, exit code 2, no tape left behind).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_dda {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;

namespace {

// A circle of radius 5 mm about (20 mm, 10 mm) on a 0.01 mm grid: 2 R is a whole number of BLU, so the DDA takes
// 8 R / BLU = 4000 steps (docs/cartesian.md).
const std::string kCircleJob = cli_job("dda_circle.toml");

void expect_bad(const Scratch& sc, const std::string& job_text, const std::string& args, const std::string& must_mention,
                bool names_file = true) {
  expect_bad_job(sc, "dda", "-o", "tape", job_text, args, must_mention, names_file ? "bad.toml" : "");
}

// `polarcam dda` on the circle job with `args`, writing `tape`: its JSON summary, the method and the 8 R / BLU = 4000
// steps checked.
json circle_summary(const Scratch& sc, const std::string& tape, const std::string& args, const char* method) {
  const std::string job = sc.write("circle.toml", kCircleJob);
  json s = cli_json("dda " + job + args + " -o " + tape + " --json");
  EXPECT_EQ(s["method"], method);
  EXPECT_EQ(s["steps_total"].get<int>(), 4000);
  return s;
}

}  // namespace

TEST(CliDda, CircleSummaryAndTapeAgree) {
  Scratch sc;
  const std::string tape = sc.path("c.tape");
  json s = circle_summary(sc, tape, "", "dda");
  EXPECT_EQ(s["steps_x"].get<int>(), 2000);
  EXPECT_EQ(s["steps_y"].get<int>(), 2000);
  EXPECT_EQ(s["start_node"], json::array({2500, 1000}));
  EXPECT_EQ(s["end_node"], s["start_node"]);
  EXPECT_TRUE(s["returns_to_start"].get<bool>());
  EXPECT_EQ(s["fit_arcs"].get<int>(), 4);
  EXPECT_EQ(s["blocks_arc"].get<int>(), 4);
  EXPECT_EQ(s["cleanup_steps"].get<int>(), 0);
  // the DDA's average speed is the programmed one to within its cycle rounding; its pulse rates swing about it
  EXPECT_NEAR(s["duration_s"].get<double>(), 2 * 3.141592653589793 * 5 / 20, 0.01);
  EXPECT_GT(s["speed_max_mps"].get<double>(), 0.02);
  EXPECT_LT(s["speed_min_mps"].get<double>(), 0.02);
  EXPECT_GT(s["speed_rms_dev_mps"].get<double>(), 0.0);
  for (const char* k : {"steps_x", "steps_y", "duration_s", "speed_min_mps", "speed_max_mps", "speed_rms_dev_mps",
                        "max_step_rate_x_hz", "max_step_rate_y_hz", "path_length_m"})
    EXPECT_TRUE(s[k].is_number()) << k;
  EXPECT_LE(s["max_step_rate_x_hz"].get<double>(), 5000.0);  // one pulse per interrupt at most

  json h = cli_json("inspect " + tape + " --json");
  EXPECT_EQ(h["axes"], "cartesian");
  EXPECT_EQ(h["rule"], "dda");
  EXPECT_EQ(h["steps_total"], s["steps_total"]);
  EXPECT_EQ(h["steps_x"], s["steps_x"]);
  EXPECT_EQ(h["start_node"], s["start_node"]);
  EXPECT_DOUBLE_EQ(h["x_resolution_m"].get<double>(), 1e-5);
  EXPECT_EQ(h["provenance"]["cartesian_machine"]["method"], "dda");
  EXPECT_DOUBLE_EQ(h["provenance"]["cartesian_machine"]["interrupt_rate_hz"].get<double>(), 5000.0);

  // the CSV replays the staircase: every node within 1.5 BLU of the circle (docs/cartesian.md)
  CliResult c = run_cli("inspect " + tape + " --csv");
  ASSERT_EQ(c.code, 0) << c.err;
  std::istringstream in(c.out);
  std::string line;
  std::getline(in, line);
  long rows = 0;
  double worst = 0;
  while (std::getline(in, line)) {
    ++rows;
    long long t;
    char axis[8];
    int dir;
    long x, y;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lld,%7[a-z],%d,%ld,%ld", &t, axis, &dir, &x, &y), 5) << line;
    ASSERT_TRUE(std::string(axis) == "x" || std::string(axis) == "y");
    ASSERT_EQ(t % 200000, 0) << "not on an interrupt: " << line;
    worst = std::max(worst, std::abs(std::hypot(x - 2000.0, y - 1000.0) - 500.0));
  }
  EXPECT_EQ(rows, 4000);
  EXPECT_LE(worst, 1.5);
}

TEST(CliDda, ExactMethodRunsAtTheProgrammedSpeed) {
  Scratch sc;
  const std::string tape = sc.path("e.tape");
  json s = circle_summary(sc, tape, " --method exact", "exact");
  EXPECT_NEAR(s["duration_s"].get<double>(), 2 * 3.141592653589793 * 5 / 20, 1e-9);
  EXPECT_NEAR(s["speed_min_mps"].get<double>(), 0.02, 0.0005);
  EXPECT_NEAR(s["speed_max_mps"].get<double>(), 0.02, 0.0005);
  EXPECT_LT(s["speed_rms_dev_mps"].get<double>(), 0.0001);
  EXPECT_FALSE(s.contains("interrupt_rate_hz"));
  CliResult j = run_cli("inspect " + tape + " --json");
  ASSERT_EQ(j.code, 0) << j.err;
  EXPECT_EQ(json::parse(j.out)["rule"], "exact");
}

TEST(CliDda, RateOptionChangesTheClock) {
  Scratch sc;
  std::string job = sc.write("circle.toml", kCircleJob);
  CliResult a = run_cli("dda " + job + " --json --rate 20000");
  CliResult b = run_cli("dda " + job + " --json --rate \"20 kHz\"");
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  json ja = json::parse(a.out), jb = json::parse(b.out);
  EXPECT_DOUBLE_EQ(ja["interrupt_rate_hz"].get<double>(), 20000.0);
  EXPECT_EQ(ja, jb);
  // a finer clock: the same steps, the pulse-rate speed closer to the programmed one
  json j5 = json::parse(run_cli("dda " + job + " --json").out);
  EXPECT_EQ(ja["steps_total"], j5["steps_total"]);
  EXPECT_LT(ja["speed_rms_dev_mps"].get<double>(), j5["speed_rms_dev_mps"].get<double>());
}

TEST(CliDda, SameJobSameBytes) {
  Scratch sc;
  std::string job = sc.write("circle.toml", kCircleJob);
  for (const char* m : {"dda", "exact"}) {
    ASSERT_EQ(run_cli("dda " + job + " --method " + m + " -o " + sc.path("a.tape")).code, 0);
    ASSERT_EQ(run_cli("dda " + job + " --method " + m + " -o " + sc.path("b.tape")).code, 0);
    EXPECT_EQ(read_file(sc.path("a.tape")), read_file(sc.path("b.tape"))) << m;
  }
}

TEST(CliDda, TestPieceExamplesRun) {
  // the standard test shapes of J. Peng's thesis (University of British Columbia, 1989): both methods, closed,
  // the same step counts
  for (const char* name : {"testpiece_square", "testpiece_diamond", "testpiece_circle"}) {
    SCOPED_TRACE(name);
    const std::string job = std::string(POLARCAM_SOURCE_DIR) + "/examples/" + name + ".toml";
    CliResult d = run_cli("dda " + job + " --json");
    CliResult e = run_cli("dda " + job + " --json --method exact");
    ASSERT_EQ(d.code, 0) << d.err;
    ASSERT_EQ(e.code, 0) << e.err;
    json jd = json::parse(d.out), je = json::parse(e.out);
    EXPECT_TRUE(jd["returns_to_start"].get<bool>());
    EXPECT_TRUE(je["returns_to_start"].get<bool>());
    EXPECT_DOUBLE_EQ(jd["speed_nominal_mps"].get<double>(), 0.02);
    EXPECT_NEAR(jd["duration_s"].get<double>(), je["duration_s"].get<double>(), 0.01 * je["duration_s"].get<double>());
  }
}

TEST(CliDda, BadInputGivesOneClearLine) {
  Scratch sc;
  expect_bad(sc, std::string(kCircleJob) + "foo = 1\n", "", "unknown key 'cartesian.foo'");
  expect_bad(sc, replace(kCircleJob, "resolution = \"0.01 mm\"", "resolution = \"-0.01 mm\""), "", "cartesian.resolution");
  expect_bad(sc, replace(kCircleJob, "resolution = \"0.01 mm\"", "resolution = \"0.01 s\""), "", "cartesian.resolution");
  expect_bad(sc, replace(kCircleJob, "tolerance = \"0.001 mm\"", "tolerance = \"0 mm\""), "", "cartesian.tolerance");
  expect_bad(sc, replace(kCircleJob, "interrupt_rate = \"5 kHz\"", "interrupt_rate = \"5 mm\""), "",
             "cartesian.interrupt_rate");
  // 20 mm/s at 0.01 mm needs 2000 DDA cycles per second
  expect_bad(sc, kCircleJob, "--rate 1000", "interrupt rate");
  expect_bad(sc, kCircleJob, "--rate \"5 mm\"", "--rate", false);
  expect_bad(sc, kCircleJob, "--rate -3", "--rate", false);
  expect_bad(sc, kCircleJob, "--method exact --rate 5000", "--rate", false);
  expect_bad(sc, replace(kCircleJob, "speed = \"20 mm/s\"", "speed = \"20 mm/s\"\naccel = \"1 m/s^2\""), "", "accel");
  expect_bad(sc, replace(kCircleJob, "radius = \"0 mm\"", "radius = \"6 mm\"\nside = \"inside\""), "", "radius");
  // the exact method takes a ramp; the DDA needs a constant feed
  std::string ramp = sc.write("ramp.toml", replace(kCircleJob, "speed = \"20 mm/s\"", "speed = \"20 mm/s\"\naccel = \"1 m/s^2\""));
  EXPECT_EQ(run_cli("dda " + ramp + " --method exact").code, 0);
  // schedules from the cut or the dynamics are not a feed: the DDA refuses them instead of running 'speed'
  const std::string milling = std::string(POLARCAM_SOURCE_DIR) + "/examples/process/contour_milling.toml";
  expect_one_line_error(run_cli("dda " + milling), "speed_profile = \"constant-force\": the DDA runs every block at a constant feed");
  EXPECT_EQ(run_cli("dda " + milling + " --method exact --json").code, 0);
}

}  // namespace tu_cli_test_cli_dda
