// Messages say what to change in the user's units: no percentages in exponent form, no type names, loads beyond
// anything the machine could hold said to be a limit of the motors only.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "tests/cli_runner.hpp"

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
