// End to end: `polarcam limits` on the documents' tools (Fussell & Gagne 1991 Table 1; Elbestawi 1980 Table 5.1)
// and `polarcam cut-force` on Elbestawi's Sec. 4.4 and case A; bad tool files refused in one line naming the key.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_limits {  // the test files of a program compile together (unity build)

using namespace polarcam::test;

namespace {
const std::string kFussell = "examples/process/fussell_table1.toml";
const std::string kElbestawi = "examples/process/elbestawi_table_5_1.toml";

const std::string kGoodTool =
    "[tool]\ndiameter = \"12.7 mm\"\nlength = \"44.5 mm\"\nteeth = 4\nhelix_angle = \"38 deg\"\n"
    "breaking_stress = \"1500 N/mm^2\"\nyoungs_modulus = \"207 GPa\"\n";
}  // namespace

// Table 1: "Stiffness of 90,200 N/cm" (the file's E = 207 GPa gives 0.23 % less).
TEST(CliLimits, FussellTable1Stiffness) {
  const auto j = cli_json("limits " + kFussell + " --json");
  EXPECT_NEAR(j["stiffness_N_per_m"].get<double>() / 100, 90200, 0.01 * 90200);
  EXPECT_DOUBLE_EQ(j["diameter_mm"].get<double>(), 12.7);
  EXPECT_EQ(j["teeth"].get<int>(), 4);
  // a printed table names the sources
  const CliResult r = run_cli("limits " + kFussell);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Eq. 5.33"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("N/cm"), std::string::npos) << r.out;
}

// Eq. 18's printed constant 7.95e-9 carries 2 pi D; polarcam's pi D gives 3.15e-9.
TEST(CliLimits, Eq18Constants) {
  const auto j = cli_json("limits " + kFussell + " --json");
  EXPECT_NEAR(j["eq18_constant_printed_2piD"].get<double>(), 7.95e-9, 0.01 * 7.95e-9);
  EXPECT_NEAR(j["eq18_constant"].get<double>(), 3.15e-9, 0.01 * 3.15e-9);
}

// Table 5.1 with the file's E = 30e6 lb/in^2: 2.0 % above Eq. 5.35's 0.0064 L^2/d, which the table rounds to 0.1 mm.
TEST(CliLimits, ElbestawiTable51ThroughOptions) {
  const double d[4] = {6.25, 12.5, 18.75, 25.0};
  const double L[3] = {50, 75, 100};
  const double ftr[3][4] = {{2.6, 1.3, 0.9, 0.6}, {5.8, 2.9, 1.9, 1.4}, {10.2, 5.1, 3.4, 2.6}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 4; ++k) {
      const auto j = cli_json("limits " + kElbestawi + " --json --diameter \"" + std::to_string(d[k]) +
                              " mm\" --length \"" + std::to_string(L[i]) + " mm\"");
      EXPECT_NEAR(j["rapid_feed_per_tooth_mm"].get<double>(), ftr[i][k], 0.021 * ftr[i][k] + 0.05);
    }
}

// Sec. 4.4: tau = 0.030 s, K = 6.3 N/mm^2/(mm/s), C = 1260 N/(mm/s).
TEST(CliCutForce, ElbestawiSec44) {
  const auto j = cli_json("cut-force --teeth 4 --spindle-speed \"500 rpm\" --radial-depth \"20 mm\" "
                          "--axial-depth \"10 mm\" --force \"4200 N\" --feed-per-tooth \"0.1 mm\" --json");
  EXPECT_NEAR(j["tau_s"].get<double>(), 0.030, 1e-9);
  EXPECT_NEAR(j["K_N_per_mm2_per_mm_per_s"].get<double>(), 6.3, 0.063);
  EXPECT_NEAR(j["C_N_per_mm_per_s"][0].get<double>(), 1260, 12.6);
  EXPECT_NEAR(j["feed_speed_mm_per_s"].get<double>(), 3.33, 0.0333);
}

// Case A: 3900 N in the rapid phase, 15 600 N at the step (printed rounded: 3905.25 and 15 621 N).
TEST(CliCutForce, ElbestawiCaseA) {
  const auto j = cli_json("cut-force --teeth 4 --spindle-speed \"500 rpm\" --radial-depth \"20 mm\" "
                          "--axial-depth \"2.5 mm\" --axial-depth \"10 mm\" --specific-force \"205 N/mm^3\" "
                          "--feed-speed \"12.7 mm/s\" --json");
  ASSERT_EQ(j["forces_N"].size(), 2u);
  EXPECT_NEAR(j["forces_N"][0].get<double>(), 3900, 39);
  EXPECT_NEAR(j["forces_N"][1].get<double>(), 15600, 156);
}

TEST(CliLimits, BadToolFilesAreRefusedInOneLine) {
  Scratch sc;
  expect_one_line_error(run_cli("limits " + sc.write("a.toml", replace(kGoodTool, "44.5 mm", "-1 mm"))),
                        "a.toml:3: key 'tool.length'");
  expect_one_line_error(run_cli("limits " + sc.write("b.toml", replace(kGoodTool, "207 GPa", "207 mm"))),
                        "b.toml:7: key 'tool.youngs_modulus'");
  expect_one_line_error(run_cli("limits " + sc.write("c.toml", replace(kGoodTool, "teeth = 4", "teeth = 4.5"))),
                        "key 'tool.teeth'");
  expect_one_line_error(run_cli("limits " + sc.write("d.toml", kGoodTool + "flutes = 4\n")), "unknown key 'tool.flutes'");
  expect_one_line_error(run_cli("limits " + sc.write("e.toml", replace(kGoodTool, "diameter = \"12.7 mm\"\n", ""))),
                        "'diameter' is missing");
  expect_one_line_error(run_cli("limits " + sc.write("f.toml", kGoodTool + "[structure]\nre_g_min = \"2e-8 m/N\"\n"
                                                     "cutting_stiffness = \"2000 N/mm^2\"\n")),
                        "key 'structure.re_g_min'");
  expect_one_line_error(run_cli("limits " + sc.write("g.toml", kGoodTool) + " --length \"0 mm\""), "--length");
  expect_one_line_error(run_cli("cut-force --teeth 4 --spindle-speed \"500 rpm\" --radial-depth \"20 mm\" "
                                "--axial-depth \"10 mm\" --force \"4200 N\""),
                        "--feed-per-tooth");
  // from a specific force, the feed is given once: both would leave one ignored
  expect_one_line_error(run_cli("cut-force --teeth 4 --spindle-speed \"500 rpm\" --radial-depth \"20 mm\" --axial-depth \"10 mm\" "
                                "--specific-force \"205 N/mm^3\" --feed-speed \"1 mm/s\" --feed-per-tooth \"0.1 mm\""),
                        "--feed-per-tooth: and --feed-speed both give the feed");
  EXPECT_EQ(run_cli("cut-force --teeth 4 --spindle-speed \"500 rpm\" --radial-depth \"20 mm\" --axial-depth \"10 mm\" "
                    "--specific-force \"205 N/mm^3\" --feed-per-tooth \"0.1 mm\"").code,
            0);
}

}  // namespace tu_cli_test_cli_limits
