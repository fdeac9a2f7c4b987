// polarcam simulate end to end: the example files of Elbestawi's A/C loop and Fussell & Gagne's band controller,
// the series as CSV, the figure, exit status 1 when a limit is exceeded, refusals of bad input in one line.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "tests/cli_runner.hpp"
#include "tests/scratch.hpp"

namespace polarcam::test {
namespace tu_cli_test_cli_simulate {  // named: the test files compile together

const std::string kExamples = std::string(POLARCAM_SOURCE_DIR) + "/examples/process/";

// Elbestawi Sec. 5.7: the dominant poles of Eq. 5.21 (-7.864 +/- j2.2481 printed) and the feed the integral
// action settles at, F_nom / K'_C = 1320 N / 224.25 N/(mm/s) = 5.886 mm/s = 353.2 mm/min.
TEST(CliSimulate, AcExample) {
  const auto j = cli_json("simulate ac " + kExamples + "elbestawi_ac_sec5_7.toml --json");
  EXPECT_NEAR(j["eq5_21"]["poles"][0]["re"].get<double>(), -7.864, 0.01 * 7.864);
  EXPECT_NEAR(j["eq5_21"]["dominant_damping"].get<double>(), 0.96, 0.01 * 0.96);
  EXPECT_NEAR(j["final_feed_mm_per_min"].get<double>(), 1320.0 / 224.25 * 60, 0.01 * 353.2);
  EXPECT_NEAR(j["final_force_N"].get<double>(), 1320.0, 0.01 * 1320);
  EXPECT_FALSE(j["limit_exceeded"].get<bool>());
}

// Sec. 5.7.2 through the options: K'_C = 346.5 N/(mm/s) is K_C = 346.5 * 4 * 10 = 13860 N/mm.
TEST(CliSimulate, AcOptionsOverrideTheFile) {
  const auto j = cli_json("simulate ac " + kExamples + "elbestawi_ac_sec5_7.toml --json --cutting-stiffness \"13860 N/mm\"");
  EXPECT_NEAR(j["cutting_rate_N_per_mm_per_s"].get<double>(), 346.5, 1e-9);
  EXPECT_NEAR(j["eq5_21"]["poles"][0]["re"].get<double>(), -6.509, 0.01 * 6.509);
  EXPECT_NEAR(j["eq5_21"]["poles"][0]["im"].get<double>(), 7.026, 0.01 * 7.026);
  const auto b = cli_json("simulate ac " + kExamples + "elbestawi_ac_sec5_5.toml --json --strategy B");
  EXPECT_EQ(b["strategy"].get<std::string>(), "B");
}

// The series: one row per 0.2 ms interrupt over the file's 3 s, t = 0 included.
TEST(CliSimulate, AcCsvAndFigure) {
  Scratch sc;
  const std::string csv = sc.path("ac.csv"), svg = sc.path("ac.svg");
  const auto r = run_cli("simulate ac " + kExamples + "elbestawi_ac_sec5_7.toml --csv " + csv + " --plot " + svg);
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(read_file(csv));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t_s,feed_mm_per_min,force_N,command_mm_per_min");
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 15001);
  EXPECT_NE(read_file(svg).find("<svg"), std::string::npos);
}

// A peak above the file's [limit] force: exit status 1, the results still printed.
TEST(CliSimulate, LimitExceededIsExitOne) {
  Scratch sc;
  const std::string f = sc.write("low.toml", replace(read_file(kExamples + "elbestawi_ac_sec5_5.toml"),
                                                      "force = \"13360 N\"", "force = \"2000 N\""));
  const auto r = run_cli("simulate ac " + f + " --json");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.out.find("\"limit_exceeded\": true"), std::string::npos);
}

// Fussell & Gagne: trial one settles inside the tooth band's feeds (24-28 in/min, Eq. 19) before the depth
// step; the limit cycle at 50 (in/min)/s with 0.25 in axial depth, none with 0.15 in.
TEST(CliSimulate, BandExamples) {
  const auto t = cli_json("simulate bands " + kExamples + "fussell_trial1.toml --json");
  const double f = t["settled_feed_before_step_in_per_min"].get<double>();
  EXPECT_GE(f, 24.0);
  EXPECT_LE(f, 28.0);
  EXPECT_FALSE(t["limit_cycle"].get<bool>());
  const auto c = cli_json("simulate bands " + kExamples + "fussell_limit_cycle.toml --json");
  EXPECT_TRUE(c["limit_cycle"].get<bool>());
  EXPECT_NEAR(c["effective_gain_in_per_min_per_s"].get<double>(), 50.0, 1e-9);
  EXPECT_EQ(c["exceeded"].size(), 0u);  // far below the tool's shank limit
  const auto s = cli_json("simulate bands " + kExamples + "fussell_limit_cycle.toml --json --axial-depth \"0.15 in\"");
  EXPECT_FALSE(s["limit_cycle"].get<bool>());
}

TEST(CliSimulate, SameInputSameBytes) {
  const auto a = run_cli("simulate bands " + kExamples + "fussell_cut1.toml --csv");
  const auto b = run_cli("simulate bands " + kExamples + "fussell_cut1.toml --csv");
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_EQ(a.out, b.out);
}

TEST(CliSimulate, BadInputIsOneLine) {
  Scratch sc;
  const std::string ac = read_file(kExamples + "elbestawi_ac_sec5_5.toml");
  expect_one_line_error(run_cli("simulate ac " + sc.write("a.toml", replace(ac, "K_ac = \"25.4 mm/s^2\"", "K_ac = \"25.4 mm/s\""))),
                        "key 'control.K_ac'");
  expect_one_line_error(run_cli("simulate ac " + sc.write("b.toml", replace(ac, "teeth = 4", "teeth = 4\nflutes = 2"))),
                        "unknown key 'cut.flutes'");
  expect_one_line_error(run_cli("simulate ac " + sc.write("c.toml", replace(ac, "rapid_feed = \"750 mm/min\"", "rapid_feed = \"1000 mm/min\""))),
                        "key 'control.rapid_feed'");
  expect_one_line_error(run_cli("simulate ac " + kExamples + "elbestawi_ac_sec5_5.toml --strategy C"), "--strategy");
  expect_one_line_error(run_cli("simulate ac " + kExamples + "elbestawi_ac_sec5_5.toml --step 0.1"), "--step");
  const std::string bands = read_file(kExamples + "fussell_trial1.toml");
  expect_one_line_error(run_cli("simulate bands " + sc.write("d.toml", replace(bands, "upper = \"200 lbf\"", "upper = \"100 lbf\""))),
                        "band.shank failure.upper");
  expect_one_line_error(run_cli("simulate bands " + sc.write("e.toml", replace(bands, "rate = \"5000 Hz\"", "rate = \"5050 Hz\""))),
                        "key 'plant.rate'");
  expect_one_line_error(run_cli("simulate bands " + kExamples + "fussell_trial1.toml --step 2"), "--step");
  expect_one_line_error(run_cli("simulate bands " + kExamples + "fussell_trial1.toml --json --csv"), "--csv");
  expect_one_line_error(run_cli("simulate bands " + kExamples + "fussell_trial1.toml --plot " + sc.path("x.gif")), "x.gif");
  expect_one_line_error(run_cli("simulate ac " + sc.path("missing.toml")), "missing.toml");
}

}  // namespace tu_cli_test_cli_simulate
}  // namespace polarcam::test
