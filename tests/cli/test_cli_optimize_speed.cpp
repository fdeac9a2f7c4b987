// End-to-end tests of `polarcam optimize-speed` and of [motion] speed_profile = "time-optimal": the JSON and CSV,
// the schedule beating the best constant speed that `analyze` passes, `digitize` and `analyze` following the
// schedule, determinism, and bad input (one line, exit status 2, no output file).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_optimize_speed {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;

namespace {

// The Ch. 5 grinding circle (safety factor 1), and the same with a time-optimal schedule under 5 cm/s.
const std::string kCircle = cli_job("grinding_circle.toml");
std::string topp_circle() {
  return replace(kCircle, "speed = \"1.52 cm/s\"", "speed = \"5 cm/s\"\nspeed_profile = \"time-optimal\"");
}

}  // namespace

TEST(CliOptimizeSpeed, BeatsTheBestConstantSpeedThatAnalyzePasses) {
  Scratch sc;
  const std::string job = sc.write("circle.toml", kCircle), csv = sc.path("plan.csv");
  const CliResult r = run_cli("optimize-speed " + job + " --json --csv " + csv);
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["verdict"], "GO");
  const double t = j["time_optimal_s"], tc = j["constant_time_s"], v = j["constant_speed_mps"];
  const double L = j["path_length_m"];
  EXPECT_NEAR(tc, L / v, 1e-9 * tc);
  EXPECT_LT(t, tc);
  EXPECT_NEAR(j["saving_s"].get<double>(), tc - t, 1e-9 * tc);
  EXPECT_LE(j["worst_torque_ratio"].get<double>(), 1.0 + 1e-3);
  ASSERT_FALSE(j["stretches"].empty());
  EXPECT_DOUBLE_EQ(j["stretches"].front()["s0_m"].get<double>(), 0.0);
  EXPECT_NEAR(j["stretches"].back()["s1_m"].get<double>(), L, 1e-12);
  // the constant speed passes `analyze`, 1 % more does not
  std::ostringstream at, above;
  at.precision(17);
  above.precision(17);
  at << v * 100 << " cm/s";
  above << v * 101 << " cm/s";
  EXPECT_EQ(run_cli("analyze " + job + " --speed \"" + at.str() + "\"").code, 0);
  EXPECT_EQ(run_cli("analyze " + job + " --speed \"" + above.str() + "\"").code, 1);
  // the CSV: one row per station, from rest to rest, its times ending at the total time
  std::istringstream in(read_file(csv));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "s_m,t_s,speed_mps,accel_mps2,phase,binding");
  size_t rows = 0;
  std::string last;
  while (std::getline(in, line)) {
    if (rows == 0) {
      EXPECT_EQ(line.substr(0, 6), "0,0,0,") << line;
    }
    last = line;
    ++rows;
  }
  EXPECT_EQ(rows, j["stations"].get<size_t>());
  EXPECT_NEAR(std::stod(last.substr(last.find(',') + 1)), t, 1e-9 * t);
  // the same bytes again
  EXPECT_EQ(run_cli("optimize-speed " + job + " --json").out, r.out);
}

TEST(CliOptimizeSpeed, TimeOptimalJobDigitizesAndAnalyzesAlongTheSchedule) {
  Scratch sc;
  const std::string job = sc.write("topp.toml", topp_circle());
  const json plan = cli_json("optimize-speed " + job + " --json");
  EXPECT_LE(plan["top_speed_mps"].get<double>(), 0.05);
  const json an = cli_json("analyze " + job + " --json");
  EXPECT_EQ(an["verdict"], "GO");
  EXPECT_NEAR(an["duration_s"].get<double>(), plan["time_optimal_s"].get<double>(), 1e-12);
  EXPECT_NEAR(an["time_optimal"]["saving_s"].get<double>(), plan["saving_s"].get<double>(), 1e-12);
  const json dg = cli_json("digitize " + job + " --json");
  EXPECT_NEAR(dg["duration_s"].get<double>(), plan["time_optimal_s"].get<double>(), 1e-9);
  EXPECT_LE(dg["last_step_s"].get<double>(), plan["time_optimal_s"].get<double>() + 1e-9);
  // the text of analyze names the schedule and the saving
  const CliResult t = run_cli("analyze " + job);
  EXPECT_EQ(t.code, 0) << t.err;
  EXPECT_NE(t.out.find("time-optimal schedule"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("saved"), std::string::npos) << t.out;
}

TEST(CliOptimizeSpeed, BadInputGivesOneClearLine) {
  Scratch sc;
  const std::string topp = topp_circle();
  expect_bad_job(sc, "optimize-speed", "--csv", "csv",
                 replace(topp, "file = \"machines/fahim1983.toml\"",
                         "file = \"machines/fahim1983.toml\"\nmax_acceleration = \"-1 m/s^2\""),
                 "", "machine.max_acceleration");
  expect_bad_job(sc, "optimize-speed", "--csv", "csv",
                 replace(topp, "file = \"machines/fahim1983.toml\"",
                         "file = \"machines/fahim1983.toml\"\nmax_jerk = \"1 m/s^3\""),
                 "", "machine.max_jerk");
  expect_bad_job(sc, "optimize-speed", "--csv", "csv",
                 replace(topp, "speed_profile = \"time-optimal\"", "speed_profile = \"time-optimal\"\naccel = \"1 m/s^2\""),
                 "", "motion.accel");
  expect_bad_job(sc, "optimize-speed", "--csv", "csv",
                 replace(topp, "speed_profile = \"time-optimal\"", "speed_profile = \"fastest\""), "",
                 "motion.speed_profile");
  // a load the machine cannot hold at this safety factor
  expect_bad_job(sc, "optimize-speed", "--csv", "csv", kCircle, "--safety-factor 1000", "safety factor");
  sc.write("machines/bare.toml", "[machine]\nradial_resolution = \"0.001 in\"\nangular_steps_per_rev = 16000\n");
  expect_bad_job(sc, "optimize-speed", "--csv", "csv", replace(kCircle, "machines/fahim1983.toml", "machines/bare.toml"),
                 "", "no dynamics");
}

}  // namespace tu_cli_test_cli_optimize_speed
