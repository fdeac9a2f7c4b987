// polarcam export: the theta-rho file, G-code in both feed modes (accepted by LinuxCNC's rs274) and the SVG drawing
// of the test sand table's limacon; the refusals (no [gcode], no r_max, a path beyond it, bad keys and options).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cam/thr_file.hpp"
#include "tests/cli_runner.hpp"
#include "tests/rs274.hpp"

namespace tu_cli_test_cli_export {  // the test files of a program compile together (unity build)

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
  const Rs274Run r = run_rs274(file);
  std::string out = r.out + r.err;
  EXPECT_EQ(r.status, 0) << out.substr(0, 2000);
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
    // a tolerance far below any machine's resolution would ask for millions of vertices: refused at once
    for (const char* fmt : {"thr", "svg", "gcode"})
      expect_bad_job(sc, "export", "-o", fmt, job, std::string("--format ") + fmt + " --tolerance \"1e-12 mm\"",
                     "--tolerance: must be at least 0.0001 mm", "");
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

namespace {

// V(s) of a schedule from `optimize-speed --csv` (s_m, t_s, speed_mps, ...): V^2 linear between the rows.
struct CsvSchedule {
  std::vector<double> s, v;
  double at(double x) const {
    if (x <= s.front()) return v.front();
    if (x >= s.back()) return v.back();
    const size_t i = static_cast<size_t>(std::upper_bound(s.begin(), s.end(), x) - s.begin()) - 1;
    const double f = (x - s[i]) / (s[i + 1] - s[i]);
    return std::sqrt(v[i] * v[i] + f * (v[i + 1] * v[i + 1] - v[i] * v[i]));
  }
  // the smallest and largest V over [a, b]: at the ends and the rows between (V^2 is monotone between rows)
  void range(double a, double b, double& lo, double& hi) const {
    lo = std::min(at(a), at(b));
    hi = std::max(at(a), at(b));
    for (size_t i = 0; i < s.size(); ++i)
      if (s[i] > a && s[i] < b) lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
  }
};

CsvSchedule read_schedule_csv(const std::string& file) {
  CsvSchedule c;
  std::istringstream in(read_file(file));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::string a, t, v;
    std::getline(f, a, ',');
    std::getline(f, t, ',');
    std::getline(f, v, ',');
    c.s.push_back(std::stod(a));
    c.v.push_back(std::stod(v));
  }
  return c;
}

// The value after `letter` in a G-code line (NaN when it has none).
double word(const std::string& line, char letter) {
  const size_t p = line.find(std::string(" ") + letter);
  if (p == std::string::npos) return std::nan("");
  return std::stod(line.substr(p + 2));
}

}  // namespace

TEST(CliExport, GcodeOfATimeOptimalJobFollowsItsSchedule) {
  Scratch sc;
  // the thesis machine with a [gcode] table: X the arm angle in radians, Y the radius in mm; limits far away
  sc.write("machines/fahim_gcode.toml", read_file(sc.path("machines/fahim1983.toml")) +
                                            "\n[gcode]\ntheta_units_per_rad = 1.0\nrho_units_per_radius = 330.2\n"
                                            "theta_max_feed = 1000.0\nrho_max_feed = 100000.0\ndecimals = 6\n");
  std::string text = read_file(std::string(POLARCAM_SOURCE_DIR) + "/examples/ch6/witch_inertial.toml");
  text = replace(text, "../machines/fahim1983.toml", "machines/fahim_gcode.toml");
  text = replace(text, "speed = \"1.524 cm/s\"", "speed = \"30 cm/s\"\nspeed_profile = \"time-optimal\"");
  const std::string job = sc.write("witch.toml", text), out = sc.path("witch.ngc"), csv = sc.path("v.csv");
  const auto j = cli_json("export " + job + " --format gcode -o " + out + " --json");
  EXPECT_EQ(j["speed_profile"], "time-optimal");
  EXPECT_EQ(j["limited"], 0);
  const auto plan = cli_json("optimize-speed " + job + " --json --csv " + csv);
  const CsvSchedule sched = read_schedule_csv(csv);
  const double L = plan["path_length_m"];
  // the moves: from the G0 to the start, each G1's ends in (theta, rho) and its duration 1 / F minutes
  struct Move {
    double th0, r0, th1, r1, T;
  };
  std::vector<Move> moves;
  std::istringstream in(read_file(out));
  std::string line;
  double th = std::nan(""), rho = 0.0;
  while (std::getline(in, line)) {
    if (line.rfind("G0 ", 0) == 0 || line.rfind("G1 ", 0) == 0) {
      const double x = word(line, 'X'), y = word(line, 'Y') / 330.2 * 0.3302;
      if (line[1] == '1') moves.push_back({th, rho, x, y, 60.0 / word(line, 'F')});
      th = x, rho = y;
    }
  }
  ASSERT_GT(moves.size(), 50u);
  // the arc length at each move's ends: the spiral (linear in theta and rho) measured at 64 points, scaled to L
  auto xy = [](double t, double r) { return std::pair{r * std::cos(t), r * std::sin(t)}; };
  std::vector<double> s0(moves.size()), s1(moves.size());
  double acc = 0.0;
  for (size_t i = 0; i < moves.size(); ++i) {
    const Move& m = moves[i];
    s0[i] = acc;
    for (int k = 1; k <= 64; ++k) {
      const auto [xa, ya] = xy(m.th0 + (m.th1 - m.th0) * (k - 1) / 64.0, m.r0 + (m.r1 - m.r0) * (k - 1) / 64.0);
      const auto [xb, yb] = xy(m.th0 + (m.th1 - m.th0) * k / 64.0, m.r0 + (m.r1 - m.r0) * k / 64.0);
      acc += std::hypot(xb - xa, yb - ya);
    }
    s1[i] = acc;
  }
  EXPECT_NEAR(acc, L, 1e-3 * L);
  std::set<double> feeds;
  size_t at_rest = 0;
  for (size_t i = 0; i < moves.size(); ++i) {
    const Move& m = moves[i];
    const double a = s0[i] * L / acc, b = s1[i] * L / acc;
    // the ball's speed at both ends of the move (the largest within it: g(rho) is monotone in rho)
    const double dth = m.th1 - m.th0, dr = m.r1 - m.r0;
    const double va = std::hypot(dr, m.r0 * dth) / m.T, vb = std::hypot(dr, m.r1 * dth) / m.T;
    double lo, hi;
    sched.range(a, b, lo, hi);
    feeds.insert(m.T);
    if (a < 1e-3 || b > L - 1e-3) {
      // within a millimetre of the start or the end at rest: the piece touching rest runs at the schedule's speed at
      // its other end (the controller starts and stops the ball), never above the schedule's speed near there
      ++at_rest;
      double lo1, hi1;
      if (a < 1e-3)
        sched.range(0.0, 1e-3, lo1, hi1);
      else
        sched.range(L - 1e-3, L, lo1, hi1);
      EXPECT_LE(std::max(va, vb), hi1 * (1.0 + 2e-3)) << "move " << i;
      continue;
    }
    EXPECT_LE(std::max(va, vb), lo * (1.0 + 2e-3)) << "move " << i << " at s = " << a << " .. " << b;
    // and not far below it where the schedule varies little
    if (hi < 1.02 * lo) {
      EXPECT_GE(std::min(va, vb), 0.9 * lo) << "move " << i;
    }
  }
  EXPECT_GT(moves.size() - at_rest, 100u);  // the moves held to the schedule strictly
  EXPECT_GT(feeds.size(), 20u);  // the feed varies along the path
  // the program's time: the schedule's, within a few per cent (every move at most the schedule's speed)
  const double t = plan["time_optimal_s"];
  EXPECT_GE(j["duration_s"].get<double>(), t * 0.99);
  EXPECT_LE(j["duration_s"].get<double>(), t * 1.08);
  expect_rs274_accepts(out);
  // the axis feed mode cannot follow a schedule; a .thr has no speed at all
  expect_one_line_error(run_cli("export " + job + " --format gcode --feed-mode axis -o " + sc.path("ax.ngc")),
                        "inverse-time");
  EXPECT_EQ(run_cli("export " + job + " --format thr -o " + sc.path("w.thr")).code, 0);
}

}  // namespace tu_cli_test_cli_export
