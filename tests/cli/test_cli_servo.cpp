// polarcam servo end to end (J. Peng 1989): the following errors and the diamond's straight-line error of the
// mismatched axes at 20 mm/s per axis, the model report (Eq. 4.101, Eq. 3.64), a polar tape and job, the exit
// status against the tolerance, the CSV and the figure, refusals of bad input in one line.
#include <gtest/gtest.h>

#include <numbers>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>
#include <utility>

#include "tests/cli_runner.hpp"
#include "tests/scratch.hpp"

namespace polarcam::test {
namespace tu_cli_test_cli_servo {  // named: the test files compile together

const std::string kDrives = std::string(POLARCAM_SOURCE_DIR) + "/examples/drives/";
const std::string kPeng = " --drives " + kDrives + "peng1989.toml";

TEST(CliServo, PengDiamondAtTwentyMillimetresPerSecondPerAxis) {
  const auto r = run_cli("servo --path diamond --feed '20*sqrt(2) mm/s' --json" + kPeng);
  EXPECT_EQ(r.code, 1) << r.err;  // corners leave 0.05 mm: NO-GO
  const auto j = nlohmann::json::parse(r.out);
  // Sec. 4.3.2: 0.2789 and 0.3267 mm printed
  EXPECT_NEAR(j["axes"][0]["following_error_mm"].get<double>(), 0.2789, 0.01 * 0.2789);
  EXPECT_NEAR(j["axes"][1]["following_error_mm"].get<double>(), 0.3267, 0.01 * 0.3267);
  // 0.034 mm along the legs (Fig. 4.35); the sign depends on the leg
  EXPECT_NEAR(std::abs(j["steady_contour_error_mm"].get<double>()), 0.034, 0.01 * 0.034);
  EXPECT_FALSE(j["within_tolerance"].get<bool>());
  EXPECT_FALSE(j["path_is_staircase"].get<bool>());
  EXPECT_EQ(j["out_of_tolerance"].size(), 3u);  // the three corners after the start
  for (const auto& iv : j["out_of_tolerance"]) {
    const double mid = (iv["t_begin_s"].get<double>() + iv["t_end_s"].get<double>()) / 2;
    EXPECT_NEAR(std::fmod(mid, 2.5), 0.02, 0.05);  // just after a corner (every 2.5 s)
  }
  // a velocity step asks the amplifier for more than its 30 A peak; 0.1 s ramps do not
  EXPECT_FALSE(j["axes"][0]["within_peak_current"].get<bool>());
  const auto ramped = nlohmann::json::parse(run_cli("servo --path diamond --ramp 0.1s --json" + kPeng).out);
  EXPECT_TRUE(ramped["axes"][0]["within_peak_current"].get<bool>());
  EXPECT_TRUE(ramped["axes"][1]["within_peak_current"].get<bool>());
  // a loose tolerance passes
  EXPECT_EQ(run_cli("servo --path diamond --tolerance 0.5mm" + kPeng).code, 0);
}

TEST(CliServo, CornerSplines) {
  const auto r = run_cli("servo --path diamond --feed '20*sqrt(2) mm/s' --corner spline --json" + kPeng);
  ASSERT_LE(r.code, 1) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["corner_splines"].size(), 3u);
  // Eq. 4.145 at the top corner (0, 50) mm: y = -2 s^2 + 2 s + 49
  const auto& A = j["corner_splines"][0]["segments"][0]["A_mm"];
  EXPECT_NEAR(A[1][1].get<double>(), -2.0, 1e-9);
  EXPECT_NEAR(A[1][2].get<double>(), 2.0, 1e-9);
  EXPECT_NEAR(A[1][3].get<double>(), 49.0, 1e-9);
  EXPECT_EQ(run_cli("servo --path circle --corner spline" + kPeng).code, 2);
}

TEST(CliServo, ModelReport) {
  const auto j = cli_json("servo --report-model --json" + kPeng);
  EXPECT_NEAR(j["axes"][0]["counts_per_Nm"].get<double>(), 7.2516, 0.001 * 7.2516);
  EXPECT_NEAR(j["axes"][0]["current_sensor_bandwidth_Hz"].get<double>(), 120.0, 0.02 * 120.0);
  EXPECT_NEAR(j["axes"][0]["following_error_s"].get<double>() * 20.0, 0.2789, 0.01 * 0.2789);
}

TEST(CliServo, PolarTapeAndJobAgree) {
  Scratch sc;
  const std::string job = std::string(POLARCAM_SOURCE_DIR) + "/examples/circle.toml";
  ASSERT_EQ(run_cli("digitize " + job + " -o " + sc.path("c.tape")).code, 0);
  const std::string drives = " --drives " + kDrives + "polar_servo.toml --json";
  const auto a = run_cli("servo " + sc.path("c.tape") + drives);
  auto b = run_cli("servo " + job + drives);
  ASSERT_EQ(a.code, b.code) << a.err << b.err;
  auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  ja.erase("input");
  jb.erase("input");
  EXPECT_EQ(ja, jb);  // the tape is the job's steps
  EXPECT_EQ(ja["machine"], "polar");
  // the drives follow the staircase of steps, which is longer than the circle of radius 5.08 cm it stands for
  EXPECT_TRUE(ja["path_is_staircase"].get<bool>());
  EXPECT_GT(ja["path_length_mm"].get<double>(), 2 * std::numbers::pi * 50.8 * 1.01);
  EXPECT_NE(run_cli("servo " + job + " --drives " + kDrives + "polar_servo.toml").out.find("along the staircase of steps"),
            std::string::npos);
  EXPECT_GT(ja["max_contour_error_mm"].get<double>(), 0.0);
  // same input, same bytes
  EXPECT_EQ(run_cli("servo " + sc.path("c.tape") + drives).out, a.out);
  // a sand-table arm's tape is refused: its radial motor is not the tool's radius
  ASSERT_EQ(run_cli("digitize " + std::string(POLARCAM_SOURCE_DIR) + "/examples/patterns/star.thr --machine " +
                    std::string(POLARCAM_SOURCE_DIR) + "/examples/machines/sand-table.toml --speed '20 mm/s' -o " +
                    sc.path("arm.tape"))
                .code,
            0);
  const auto arm = run_cli("servo " + sc.path("arm.tape") + " --drives " + kDrives + "polar_servo.toml");
  EXPECT_EQ(arm.code, 2);
  EXPECT_NE(arm.err.find("sand-table arm"), std::string::npos) << arm.err;
  // a polar tape with Cartesian drives is refused
  const auto bad = run_cli("servo " + sc.path("c.tape") + kPeng);
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("[r] and [theta]"), std::string::npos) << bad.err;
}

// The limacon on both machines: its polar tape through polar drives, its Cartesian DDA tape (named .dda: a tape
// is known by its first bytes) through Peng's drives. Each says where it would leave a tight tolerance and passes a
// loose one; every interval it names lies on the path, with its largest error above the tolerance.
TEST(CliServo, LimaconPolarAndDdaTapesShowWhereTheyLeaveTolerance) {
  Scratch sc;
  const std::string job = std::string(POLARCAM_SOURCE_DIR) + "/examples/limacon.toml";
  ASSERT_EQ(run_cli("digitize " + job + " -o " + sc.path("l.tape")).code, 0);
  ASSERT_EQ(run_cli("dda " + job + " -o " + sc.path("l.dda")).code, 0);
  for (const auto& [tape, drives] : {std::pair{sc.path("l.tape"), std::string("polar_servo.toml")},
                                     std::pair{sc.path("l.dda"), std::string("peng1989.toml")}}) {
    const std::string base = "servo " + tape + " --drives " + kDrives + drives + " --json --tolerance ";
    const auto loose = run_cli(base + "'1 mm'");
    ASSERT_EQ(loose.code, 0) << tape << ": " << loose.err;
    const auto jl = nlohmann::json::parse(loose.out);
    const double worst = jl["max_contour_error_mm"].get<double>(), length = jl["path_length_mm"].get<double>();
    EXPECT_GT(worst, 0.0);
    EXPECT_LT(worst, 1.0);
    EXPECT_TRUE(jl["out_of_tolerance"].empty());
    const double tight = 0.5 * worst;  // half the largest error: some stretches leave it
    const auto r = run_cli(base + "'" + std::to_string(tight) + " mm'");
    EXPECT_EQ(r.code, 1) << tape << ": " << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["within_tolerance"], false);
    ASSERT_FALSE(j["out_of_tolerance"].empty()) << tape;
    double largest = 0;
    for (const auto& iv : j["out_of_tolerance"]) {
      EXPECT_LE(iv["s_begin_mm"].get<double>(), iv["s_end_mm"].get<double>());
      EXPECT_GE(iv["s_begin_mm"].get<double>(), 0.0);
      EXPECT_LE(iv["s_end_mm"].get<double>(), length * (1 + 1e-9));
      EXPECT_GT(iv["max_contour_error_mm"].get<double>(), tight);
      largest = std::max(largest, iv["max_contour_error_mm"].get<double>());
    }
    EXPECT_DOUBLE_EQ(largest, worst) << "the worst point lies in one of the intervals";
  }
}

TEST(CliServo, CsvAndFigure) {
  Scratch sc;
  const auto r = run_cli("servo --path square --csv " + sc.path("s.csv") + " --plot " + sc.path("s.svg") + kPeng);
  EXPECT_EQ(r.code, 1) << r.err;
  std::ifstream in(sc.path("s.csv"));
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "t_s,ref_x_mm,ref_y_mm,act_x_mm,act_y_mm,contour_error_mm");
  size_t rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 10201u);  // 4 sides of 50 mm at 20 mm/s, then 0.2 s held, every 1 ms
  EXPECT_GT(std::filesystem::file_size(sc.path("s.svg")), 1000u);
}

TEST(CliServo, RefusesBadInput) {
  Scratch sc;
  struct Case {
    std::string args, where;
  };
  const std::string bad = sc.write("bad.toml", "[x]\nR_a = \"0.4 m\"\n");
  for (const Case& c : std::vector<Case>{
           {"servo --path hexagon" + kPeng, "--path"},
           {"servo --path square --feed 20mm" + kPeng, "--feed"},
           {"servo --path square --tolerance -1mm" + kPeng, "--tolerance"},
           {"servo --path square --drives " + bad, "bad.toml:2: key 'x.R_a'"},
           {"servo" + kPeng, "--path"},
           {"servo --path square --integral 1e9" + kPeng, "--integral"},
       }) {
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.code, 2) << c.args;
    EXPECT_NE(r.err.find(c.where), std::string::npos) << c.args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

}  // namespace tu_cli_test_cli_servo
}  // namespace polarcam::test
