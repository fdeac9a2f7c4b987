// polarcam export: the theta-rho file, G-code in both feed modes (accepted by LinuxCNC's rs274) and the SVG drawing
// of the test sand table's limacon; the refusals (no [gcode], no r_max, a path beyond it, bad keys and options).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "cam/thr_file.hpp"
#include "tests/cli_runner.hpp"

using namespace polarcam;
using namespace polarcam::test;

namespace {

const std::string kData = std::string(POLARCAM_SOURCE_DIR) + "/tests/data/cli/";

std::string sand_machine() { return read_file(kData + "machines/sand_table.toml"); }

// A scratch directory with the sand table's machine file (as given, or edited) and the limacon job.
struct SandScratch : Scratch {
  explicit SandScratch(const std::string& machine = sand_machine()) {
    write("machines/sand_table.toml", machine);
    job = write("limacon.toml", cli_job("sand_limacon.toml"));
  }
  std::string job;
};

// rs274 exits 0 and says nothing of an error for the file.
void expect_rs274_accepts(const std::string& file) {
  ASSERT_STRNE(POLARCAM_RS274, "") << "rs274 (Debian package linuxcnc-uspace) is needed for this test";
  const std::string log = file + ".rs274";
  const int st = std::system((std::string(POLARCAM_RS274) + " -g " + file + " </dev/null >" + log + " 2>&1").c_str());
  std::string out = read_file(log);
  std::remove(log.c_str());
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << out.substr(0, 2000);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  EXPECT_EQ(out.find("error"), std::string::npos) << out.substr(0, 2000);
  EXPECT_NE(out.find("program_end()"), std::string::npos);
}

}  // namespace

TEST(CliExport, ThetaRhoFileOfTheLimacon) {
  SandScratch sc;
  const std::string out = sc.path("limacon.thr");
  const auto j = cli_json("export " + sc.job + " --format thr -o " + out + " --tolerance \"0.05 mm\" --json");
  const ThrPattern p = read_thr(out);
  EXPECT_EQ(j["vertices"], p.vertices.size());
  EXPECT_GT(p.vertices.size(), 20u);
  // the start: the limacon's point at theta1 = 0, b + a = 127 mm from its pole, 127 - 12.7 mm from the machine's,
  // of the table's 200 mm
  EXPECT_NEAR(p.vertices.front().rho, 114.3 / 200.0, 1e-12);
  EXPECT_NEAR(p.vertices.front().theta, 0.0, 1e-12);
  // a closed path about the pole: one turn, back at its start
  EXPECT_NEAR(p.vertices.back().theta, 2 * std::acos(-1.0), 1e-9);
  EXPECT_NEAR(p.vertices.back().rho, 114.3 / 200.0, 1e-12);
  for (const ThetaRho& v : p.vertices) EXPECT_LE(v.rho, 1.0);
  const std::string text = read_file(out);
  EXPECT_NE(text.find("# polarcam export of limacon.toml\n"), std::string::npos);
  EXPECT_NE(text.find("# contour: limacon"), std::string::npos);
  EXPECT_NE(text.find("# tolerance: 0.05 mm"), std::string::npos);
  EXPECT_EQ(text.find(sc.dir.string()), std::string::npos);  // no directories in the file
  // the same bytes again
  const std::string again = sc.path("again.thr");
  cli_json("export " + sc.job + " --format thr -o " + again + " --tolerance \"0.05 mm\" --json");
  EXPECT_EQ(read_file(again), text);
}

TEST(CliExport, GcodeAtConstantBallSpeedAndAtConstantAxisFeed) {
  SandScratch sc;
  const std::string it = sc.path("limacon.ngc"), ax = sc.path("limacon-axis.ngc");
  const auto j = cli_json("export " + sc.job + " --format gcode -o " + it + " --json");
  EXPECT_EQ(j["feed_mode"], "inverse-time");
  EXPECT_LE(j["max_speed_error_pct"].get<double>(), 1.0);
  EXPECT_EQ(j["limited"], 0);
  // every move within 1 % of 20 mm/s: the time is the path's length at that speed, within 1 %
  const double expected = j["path_length_m"].get<double>() / 0.02;
  EXPECT_NEAR(j["duration_s"].get<double>(), expected, 0.01 * expected);
  const std::string g = read_file(it);
  EXPECT_NE(g.find("\nG93\nG0 X0.0000 Y114.3000 (to the start)\n"), std::string::npos) << g.substr(0, 400);
  EXPECT_NE(g.find("\nG94\nM2\n"), std::string::npos);
  expect_rs274_accepts(it);

  const auto ja = cli_json("export " + sc.job + " --format gcode --feed-mode axis -o " + ax + " --json");
  EXPECT_EQ(ja["feed_mode"], "axis");
  EXPECT_EQ(ja["g1"], ja["vertices"].get<int>() - 1);  // one move per segment
  const std::string ga = read_file(ax);
  EXPECT_NE(ga.find("\nG94\nG0 X0.0000 Y114.3000 (to the start)\n"), std::string::npos);
  EXPECT_NE(ga.find(" F200.0000\n"), std::string::npos);
  EXPECT_EQ(ga.find("G93"), std::string::npos);
  expect_rs274_accepts(ax);
}

TEST(CliExport, SvgDrawingOfTheToolPath) {
  SandScratch sc;
  const std::string out = sc.path("limacon.svg");
  const CliResult r = run_cli("export " + sc.job + " --format svg -o " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string s = read_file(out);
  EXPECT_EQ(s.rfind("<?xml", 0), 0u);
  // the table's 200 mm radius and a 5 mm margin
  EXPECT_NE(s.find("width=\"410.0000mm\" height=\"410.0000mm\" viewBox=\"-205.0000 -205.0000 410.0000 410.0000\""),
            std::string::npos);
  EXPECT_NE(s.find("<polyline points=\"114.3000,0.0000 "), std::string::npos);
  EXPECT_NE(s.find("id=\"start\""), std::string::npos);
  EXPECT_NE(r.out.find("limacon.svg"), std::string::npos);
}

TEST(CliExport, RefusesWhatItCannotExport) {
  // the thesis machine has no [gcode] table, and this job lifts its r_max
  {
    Scratch sc;
    const std::string job = cli_job("small_circle.toml");
    expect_bad_job(sc, "export", "-o", "ngc", job, "--format gcode", "no [gcode] table");
    expect_bad_job(sc, "export", "-o", "thr", job, "--format thr", "needs r_max");
  }
  // a path beyond the table
  {
    SandScratch sc;
    const std::string big = replace(replace(cli_job("sand_limacon.toml"), "a = \"5.08 cm\"", "a = \"12 cm\""),
                                    "b = \"7.62 cm\"", "b = \"10 cm\"");
    expect_bad_job(sc, "export", "-o", "thr", big, "--format thr", "beyond the machine's r_max (200 mm)");
    expect_bad_job(sc, "export", "-o", "ngc", big, "--format gcode", "beyond the [gcode] table radius (200 mm)");
  }
  // options
  {
    SandScratch sc;
    const std::string job = cli_job("sand_limacon.toml");
    expect_bad_job(sc, "export", "-o", "x", job, "--format dxf", "--format: must be thr, gcode or svg", "");
    expect_bad_job(sc, "export", "-o", "thr", job, "--format thr --feed-mode axis", "--feed-mode", "");
    expect_bad_job(sc, "export", "-o", "ngc", job, "--format gcode --feed-mode fast", "--feed-mode", "");
    expect_bad_job(sc, "export", "-o", "thr", job, "--format thr --tolerance \"0 mm\"", "--tolerance", "");
    expect_bad_job(sc, "export", "-o", "thr", job, "--format thr --tolerance \"2 s\"", "--tolerance", "");
  }
}

TEST(CliExport, GcodeKeysAreCheckedInTheMachineFile) {
  struct Case {
    std::string from, to, mentions;
  };
  const Case cases[] = {
      {"theta_max_feed = 120.0", "theta_max_fed = 120.0", "unknown key 'gcode.theta_max_fed'"},
      {"rho_max_feed = 3000.0", "", "key 'gcode.rho_max_feed': is missing"},
      {"theta_max_feed = 120.0", "theta_max_feed = -1.0", "'gcode.theta_max_feed'"},
      {"rho_axis = \"Y\"", "rho_axis = \"X\"", "'gcode.rho_axis'"},
      {"feed_mode = \"inverse_time\"", "feed_mode = \"fast\"", "'gcode.feed_mode'"},
      {"decimals = 4", "decimals = 12", "'gcode.decimals'"},
      {"header = [\"G21\", \"G90\"]", "header = \"G21\"", "'gcode.header'"},
      {"axis_feed = 200.0", "axis_feed = 0.0", "'gcode.axis_feed'"},
  };
  for (const Case& c : cases) {
    SandScratch sc(replace(sand_machine(), c.from, c.to));
    expect_bad_job(sc, "export", "-o", "ngc", cli_job("sand_limacon.toml"), "--format gcode", c.mentions,
                   "sand_table.toml:");
  }
  // a machine file's other tables are still refused
  SandScratch sc(sand_machine() + "\n[spindle]\nspeed = 1\n");
  expect_bad_job(sc, "export", "-o", "ngc", cli_job("sand_limacon.toml"), "--format gcode", "unknown section 'spindle'",
                 "sand_table.toml:");
}
