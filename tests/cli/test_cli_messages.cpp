// Messages say what to change in the user's units: no percentages in exponent form, no type names, loads beyond
// anything the machine could hold said to be a limit of the motors only.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <string>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_messages {  // the test files of a program compile together (unity build)

using namespace polarcam::test;

namespace {

std::string example(const std::string& rel) { return std::string(POLARCAM_SOURCE_DIR) + "/examples/" + rel; }

}  // namespace

// The thesis's circle with 43.77 kg on its 0.9 kg carriage: the motors' torque alone would carry thousands of
// kilograms; the capacity says that is a theoretical limit, in plain numbers.
TEST(Messages, CapacityCallsAHugeLoadATheoreticalLimitOfTheMotors) {
  const CliResult r = run_cli("capacity " + example("ch6/circle_inertial.toml"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("theoretical limit of the motors"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("carriage's own 0.9 kg"), std::string::npos) << r.out;
  EXPECT_FALSE(std::regex_search(r.out, std::regex("[0-9]e[+-][0-9]+ times"))) << r.out;
  const nlohmann::json j = cli_json("capacity " + example("ch6/circle_inertial.toml") + " --json");
  EXPECT_EQ(j["load_theoretical_only"], true);
  // --curve N prints the curve in the text too, the same values as the JSON's
  const CliResult curve = run_cli("capacity " + example("ch6/circle_inertial.toml") + " --curve 5");
  ASSERT_EQ(curve.code, 0) << curve.err;
  const nlohmann::json jc = cli_json("capacity " + example("ch6/circle_inertial.toml") + " --curve 5 --json");
  ASSERT_EQ(jc["curve"].size(), 5u) << jc.dump();
  const size_t head = curve.out.find("  curve      ");
  ASSERT_NE(head, std::string::npos) << curve.out;
  size_t lines = 0;
  for (size_t at = curve.out.find(" cm/s: ", head); at != std::string::npos; at = curve.out.find(" cm/s: ", at + 1)) ++lines;
  EXPECT_EQ(lines, 5u) << curve.out;
}

// At a crawl the drives need a tiny share of their torque: the report's margins are ratios, not "5.55e+04 %".
TEST(Messages, ReportMarginsArePlainRatios) {
  Scratch sc;
  const std::string out = sc.path("r.html");
  const CliResult r = run_cli("report " + example("ch6/circle_inertial.toml") + " --speed \"0.5 mm/s\" -o " + out +
                              " --map-size 5 --max-evaluations 30 --threads 2");
  ASSERT_TRUE(r.code == 0 || r.code == 1) << r.err;
  const std::string html = read_file(out);
  ASSERT_FALSE(html.empty());
  EXPECT_FALSE(std::regex_search(html, std::regex("[0-9]e[+-][0-9]+ ?%"))) << "a percentage in exponent form";
  EXPECT_NE(html.find("times what it needs"), std::string::npos);
  EXPECT_NE(html.find("theoretical limit of the motors"), std::string::npos);
}

// The thesis's circle at 20 cm/s: the radial axis moves at up to 20 cm/s, i.e. 7874 tape steps of 0.001 in per
// second, and each tape step is 8 motor steps (0.001 in x 20 screw turns per inch x 400 motor steps per turn):
// about 63 000 motor steps/s against the drives' 5500 steps/s. digitize still writes the tape (exit 0) and warns
// in one line naming the axis, the rate and the limit; at the job's own 1.52 cm/s it says nothing.
TEST(Messages, DigitizeWarnsWhenAMotorWouldStepFasterThanItsLimit) {
  Scratch sc;
  const std::string tape = sc.path("fast.tape");
  const CliResult r = run_cli("digitize " + example("ch5/circle.toml") + " --speed \"20 cm/s\" -o " + tape);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(tape));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("radial motor"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("max_step_rate of 5500 steps/s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" x 8)"), std::string::npos) << r.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.err, m, std::regex("step at ([0-9.e+]+) steps/s"))) << r.err;
  // the circle's largest |dr/ds| is 1 (where the path runs along the arm), so the motor rate is V / dR x 8
  const double expected = 0.20 / 0.0000254 * 8;
  EXPECT_NEAR(std::stod(m[1].str()), expected, 1e-3 * expected);
  EXPECT_EQ(r.out.find("warning"), std::string::npos);  // the summary on stdout stays clean

  const CliResult slow = run_cli("digitize " + example("ch5/circle.toml") + " -o " + sc.path("slow.tape"));
  ASSERT_EQ(slow.code, 0) << slow.err;
  EXPECT_EQ(slow.err, "");
}

// analyze names the step rate in its NO-GO verdict even when the torque fails first.
TEST(Messages, AnalyzeNamesAnExceededStepRate) {
  const CliResult r = run_cli("analyze " + example("ch5/circle.toml") + " --speed \"2 cm/s\"");
  EXPECT_EQ(r.code, 1) << r.err;
  const size_t v = r.out.find("verdict");
  ASSERT_NE(v, std::string::npos) << r.out;
  const std::string verdict = r.out.substr(v, r.out.find('\n', v) - v);
  EXPECT_NE(verdict.find("NO-GO"), std::string::npos) << verdict;
  EXPECT_NE(verdict.find("radial motor must also step at"), std::string::npos) << verdict;
  EXPECT_NE(verdict.find("above its limit of 5500 Hz"), std::string::npos) << verdict;
}

}  // namespace tu_cli_test_cli_messages
