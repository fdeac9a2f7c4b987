// End to end: `polarcam process` on the constant-force example (examples/process/contour_milling.toml): the force
// held at the nominal force and within the tool's limits, the stretches covering the path, the same time as the
// tape `digitize` writes, the same bytes twice; a job whose own speed overloads the tool (exit status 1); a job
// without a milling cut refused in one line.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_process {  // the test files of a program compile together (unity build)

using namespace polarcam::test;

namespace {
const std::string kJob = "examples/process/contour_milling.toml";
}  // namespace

TEST(CliProcess, ConstantForceExample) {
  Scratch sc;
  const std::string csv = sc.path("m.csv"), svg = sc.path("m.svg");
  const auto j = cli_json("process " + kJob + " --json --csv " + csv + " --plot " + svg);
  EXPECT_EQ(j["profile"], "constant-force");
  EXPECT_EQ(j["mode"], "up");
  EXPECT_DOUBLE_EQ(j["nominal_force_N"].get<double>(), 85.0);
  EXPECT_LE(j["max_mean_force_N"].get<double>(), 85.0 * (1 + 1e-9));
  EXPECT_GT(j["max_mean_force_N"].get<double>(), 84.0);
  EXPECT_TRUE(j["exceeded"].empty());
  EXPECT_LE(j["max_peak_force_N"].get<double>(), j["limits"]["breakage_force_N"].get<double>());
  EXPECT_LE(j["max_normal_force_N"].get<double>(), j["limits"]["deflection_force_limit_N"].get<double>());
  // the stretches cover the path: the entry first, then the nominal force
  const auto& st = j["stretches"];
  ASSERT_GE(st.size(), 2u);
  EXPECT_EQ(st[0]["binding"], "entry");
  EXPECT_DOUBLE_EQ(st[0]["s0_m"].get<double>(), 0.0);
  EXPECT_NEAR(st.back()["s1_m"].get<double>(), j["path_length_m"].get<double>(), 1e-9);
  for (size_t i = 1; i < st.size(); ++i) EXPECT_DOUBLE_EQ(st[i]["s0_m"].get<double>(), st[i - 1]["s1_m"].get<double>());
  // the series: one row per station, t at the last row the duration
  const std::string text = read_file(csv);
  std::istringstream in(text);
  std::string line, last;
  size_t rows = 0;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("s_m,t_s,speed_mm_per_s,", 0), 0u) << line;
  while (std::getline(in, line)) ++rows, last = line;
  EXPECT_GT(rows, 1000u);
  const double t_last = std::stod(last.substr(last.find(',') + 1));
  EXPECT_NEAR(t_last, j["duration_s"].get<double>(), 1e-6);
  EXPECT_NE(read_file(svg).find("<svg"), std::string::npos);
  // the tape takes the same time
  const auto d = cli_json("digitize " + kJob + " --json");
  EXPECT_NEAR(d["duration_s"].get<double>(), j["duration_s"].get<double>(), 1e-6 * j["duration_s"].get<double>());
  // determinism
  const std::string csv2 = sc.path("m2.csv");
  const CliResult again = run_cli("process " + kJob + " --json --csv " + csv2);
  EXPECT_EQ(read_file(csv2), text);
  // analyze sees the milling load
  const CliResult a = run_cli("analyze " + kJob + " --json");
  EXPECT_TRUE(a.code == 0 || a.code == 1) << a.err;
  EXPECT_NE(a.out.find("\"milling\""), std::string::npos);
}

// A constant feed of 15 mm/s slotting 25 mm deep: the perpendicular force is far above the deflection limit.
TEST(CliProcess, AJobsOwnSpeedAboveALimitExitsOne) {
  Scratch sc;
  std::string job = read_file(kJob);
  job = replace(job, "file = \"../machines/fahim1983.toml\"", "file = \"machines/fahim1983.toml\"");
  job = replace(job, "tool = \"fussell_table1.toml\"", "tool = \"" + std::string(POLARCAM_SOURCE_DIR) +
                                                       "/examples/process/fussell_table1.toml\"");
  job = replace(job, "speed_profile = \"constant-force\"\n", "");
  job = replace(job, "nominal_force = \"85 N\"", "");
  job = replace(job, "axial_depth = \"0.25 in\"", "axial_depth = \"25 mm\"");
  job = replace(job, "radial_width = \"2 mm\"", "radial_width = \"12.7 mm\"");
  const CliResult r = run_cli("process " + sc.write("slot.toml", job) + " --json");
  EXPECT_EQ(r.code, 1) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["profile"], "job");
  bool deflection = false;
  for (const auto& e : j["exceeded"]) deflection |= e == "deflection_force";
  EXPECT_TRUE(deflection) << r.out;
}

TEST(CliProcess, AJobWithoutAMillingCutIsRefused) {
  const CliResult r = run_cli("process examples/limacon.toml --json");
  expect_one_line_error(r, "milling");
  EXPECT_NE(r.err.find("limacon.toml"), std::string::npos) << r.err;
}

}  // namespace tu_cli_test_cli_process
