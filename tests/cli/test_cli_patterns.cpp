// Pattern files as jobs (`polarcam digitize PATTERN --machine M --speed V`) on the example sand table: the example
// patterns, a dozen theta-rho patterns made here to exercise what public collections hold (cumulative theta past
// +-100 rad, centre crossings, repeated points, comments, CRLF, 10^5 points), the step counts of a pattern's tape
// against a count made here from its vertices, and bad patterns refused in one line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_patterns {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;

namespace {

const std::string kSource = POLARCAM_SOURCE_DIR;
const std::string kTable = kSource + "/examples/machines/sand-table.toml";

// The example sand table's grid and coupling, as its machine file states them (worked out here, not read).
const double kDr = 0.040 / (200 * 16);                 // m per radial step
const double kStepsPerRev = 200 * 16 * 6.25;           // angular steps per turn
const double kDtheta = 2 * M_PI / kStepsPerRev;
const double kCoupling = 2560 * kDr / (2 * M_PI);       // m per radian
const double kRadius = 0.200;

struct Vertex {
  double theta, rho;
};

std::string thr_text(const std::vector<Vertex>& v, const std::string& eol = "\n") {
  std::ostringstream os;
  os.precision(17);
  os << "# made by the test" << eol;
  for (const Vertex& p : v) os << p.theta << " " << p.rho << eol;
  return os.str();
}

std::string digitize_args(const std::string& file) {
  return "digitize " + file + " --machine " + kTable + " --speed \"40 mm/s\" --json";
}

// Steps of each motor that a tape of these vertices must hold: on each segment both motor coordinates are linear,
// so a motor moves by the difference of its nearest nodes at the two ends (repeated vertices move nothing).
void expected_steps(const std::vector<Vertex>& v, long long& radial, long long& angular) {
  radial = angular = 0;
  auto node = [](double q, double res) { return static_cast<long long>(std::floor(q / res + 0.5)); };
  for (size_t k = 1; k < v.size(); ++k) {
    const double qa = v[k - 1].rho * kRadius + kCoupling * v[k - 1].theta, qb = v[k].rho * kRadius + kCoupling * v[k].theta;
    radial += std::llabs(node(qb, kDr) - node(qa, kDr));
    angular += std::llabs(node(v[k].theta, kDtheta) - node(v[k - 1].theta, kDtheta));
  }
}

}  // namespace

TEST(Patterns, EveryExamplePatternDigitizesOnTheSandTable) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(kSource + "/examples/patterns")) {
    if (e.path().extension() != ".thr") continue;
    SCOPED_TRACE(e.path().string());
    const json j = cli_json(digitize_args(e.path().string()));
    EXPECT_GT(j.value("steps_total", 0), 1000) << j.dump();
    EXPECT_EQ(j.value("contours", 0), 1);
    ++n;
  }
  EXPECT_GE(n, 3);
}

TEST(Patterns, ADozenPatternsOfTheUsualKindsImportAndDigitize) {
  Scratch sc;
  std::vector<std::pair<std::string, std::vector<Vertex>>> cases;
  auto add = [&](const std::string& name, std::vector<Vertex> v) { cases.push_back({name, std::move(v)}); };
  {  // theta far past +100 rad: 40 turns out
    std::vector<Vertex> v;
    for (int i = 0; i <= 4000; ++i) v.push_back({i * 2 * M_PI / 100, i / 4000.0});
    add("wound-up", v);
  }
  {  // theta far below -100 rad: 30 turns the other way, rim to centre
    std::vector<Vertex> v;
    for (int i = 0; i <= 3000; ++i) v.push_back({-i * 2 * M_PI / 100, 1 - i / 3000.0});
    add("wound-down", v);
  }
  {  // through the centre: diameters, the arm turning half a turn at rho = 0
    std::vector<Vertex> v;
    for (int k = 0; k < 10; ++k) {
      const double a = k * 0.3;
      v.insert(v.end(), {{a, 1}, {a, 0}, {a + M_PI, 0}, {a + M_PI, 1}});
    }
    add("diameters", v);
  }
  {  // straight through the centre without a turn: in to rho = 0 and out on the same theta (a cusp at the centre)
    add("bounce", {{0.2, 0.9}, {0.2, 0.0}, {0.2, 0.7}, {1.2, 0.7}, {1.2, 0.0}, {4.0, 0.6}});
  }
  {  // repeated points, as exporters write at segment joins
    std::vector<Vertex> v;
    for (int i = 0; i <= 200; ++i) {
      v.push_back({i * 0.05, 0.3 + 0.2 * std::sin(i * 0.1)});
      if (i % 10 == 0) v.push_back(v.back());
    }
    add("repeats", v);
  }
  {  // starts and ends at the rim, a full circle at the rim first
    add("rim", {{0, 1}, {2 * M_PI, 1}, {2 * M_PI + 1, 0.5}, {2 * M_PI + 3, 1}});
  }
  {  // a pure turn of the arm at the centre
    add("centre-turn", {{0, 0.5}, {0, 0}, {10, 0}, {10, 0.5}});
  }
  {  // decreasing and increasing theta, back and forth (a zig-zag sweep)
    std::vector<Vertex> v;
    for (int i = 0; i <= 100; ++i) v.push_back({(i % 2 ? 3.0 : 0.0) + 0.01 * i, 0.1 + 0.008 * i});
    add("zigzag", v);
  }
  {  // pure radial lines (equal thetas) and pure arcs (equal rhos)
    add("lines-arcs", {{0, 0.1}, {0, 0.9}, {1, 0.9}, {1, 0.1}, {2, 0.1}, {2, 0.9}});
  }
  {  // a dense rose, 20 000 points
    std::vector<Vertex> v;
    for (int i = 0; i <= 20000; ++i) v.push_back({i * 2 * M_PI / 20000, 0.5 + 0.45 * std::cos(7 * i * 2 * M_PI / 20000)});
    add("dense-rose", v);
  }
  {  // 10^5 points: a spiral of 100 turns from the rim in
    std::vector<Vertex> v;
    for (int i = 0; i <= 100000; ++i) v.push_back({i * 2 * M_PI / 1000, 1 - i / 100000.0});
    add("big", v);
  }
  {  // tiny moves: many points closer than a step
    std::vector<Vertex> v;
    for (int i = 0; i <= 2000; ++i) v.push_back({1 + i * 1e-6, 0.5 + i * 1e-7});
    add("tiny", v);
  }
  ASSERT_GE(cases.size(), 12u);
  for (const auto& [name, v] : cases) {
    SCOPED_TRACE(name);
    const std::string file = sc.write(name + ".thr", thr_text(v, name == "rim" ? "\r\n" : "\n"));
    const json j = cli_json(digitize_args(file));
    long long radial, angular;
    expected_steps(v, radial, angular);
    EXPECT_EQ(j.value("steps_radial", -1LL), radial);
    EXPECT_EQ(j.value("steps_angular", -1LL), angular);
  }
}

TEST(Patterns, TheTapeOfAPatternInspectsAndEndsWhereTheLastVertexIs) {
  Scratch sc;
  const std::vector<Vertex> v = {{0.5, 0.25}, {0.5, 0.0}, {0.5 + M_PI, 0.0}, {9.0, 0.75}, {-4.0, 0.5}};
  const std::string file = sc.write("p.thr", thr_text(v)), tape = sc.path("p.tape");
  const json j = cli_json("digitize " + file + " --machine " + kTable + " --speed \"25 mm/s\" -o " + tape + " --json");
  const json in = cli_json("inspect " + tape + " --json");
  EXPECT_EQ(in.value("steps_total", 0LL), j.value("steps_total", -1LL)) << in.dump();
  // the last vertex's nodes: the radial motor at rho R + c theta, the arm at theta (no whole-turn shift: the
  // pattern starts within the first turn)
  auto node = [](double q, double res) { return static_cast<long long>(std::floor(q / res + 0.5)); };
  EXPECT_EQ(j["end_node"][0].get<long long>(), node(0.5 * kRadius + kCoupling * -4.0, kDr));
  EXPECT_EQ(j["end_node"][1].get<long long>(), node(-4.0, kDtheta));
}

TEST(Patterns, BadPatternsAreOneLineErrors) {
  Scratch sc;
  auto bad = [&](const std::string& text, const std::string& must_mention) {
    const std::string file = sc.write("bad.thr", text);
    const CliResult r = run_cli(digitize_args(file));
    expect_one_line_error(r, must_mention);
  };
  bad("0 0.5\n1 1.5\n", "bad.thr:2");
  bad("0 0.5\n1 1.5\n", "outside 0..1");
  bad("0 0.5\n1 1.0000001\n", "rho 1.0000001 is outside 0..1");  // printed as read, not rounded to look legal
  bad("0 0.5\n# c\n1 abc\n", "bad.thr:3");
  bad("0 0.5\n1 nan\n", "bad.thr:2");
  bad("0 0.5 7\n", "expected two numbers");
  bad("# nothing\n", "no points");
  bad("0 0.5\n0 0.5\n", "one distinct point");
  const std::string good = sc.write("good.thr", "0 0.5\n1 0.5\n");
  expect_one_line_error(run_cli("digitize " + good + " --speed \"40 mm/s\""), "--machine");
  expect_one_line_error(run_cli("digitize " + good + " --machine " + kTable), "--speed");
  expect_one_line_error(run_cli("digitize " + good + " --machine " + kTable + " --speed \"40 mm\""), "--speed");
  const std::string no_rim = sc.write("m.toml", "[machine]\nradial_resolution = \"0.01 mm\"\nangular_steps_per_rev = 3200\n");
  expect_one_line_error(run_cli("digitize " + good + " --machine " + no_rim + " --speed \"40 mm/s\""), "r_max");
  // --machine is for patterns: a job names its machine
  expect_one_line_error(run_cli("digitize " + kSource + "/examples/limacon.toml --machine " + kTable), "--machine");
  // a UTF-8 byte order mark before the first line (as some editors on Windows write) is not part of the numbers
  const json bom = cli_json(digitize_args(sc.write("bom.thr", "\xEF\xBB\xBF" "0 0.5\r\n1 0.5\r\n")));
  EXPECT_GT(bom.value("steps_angular", 0), 0);
  // theta beyond any tape: 1e9 rad is 1.59e8 turns, 3.18e12 angular steps of this table (20 000 a turn); refused at
  // once by every command that takes the pattern on a machine, instead of walked for hours
  const std::string far = sc.write("far.thr", "0 0\n1e9 0.5\n");
  for (const std::string& cmd : {std::string("digitize ") + far + " -o " + sc.path("far.tape") + " --speed \"40 mm/s\"",
                                 "check " + far + " --speed \"40 mm/s\"", "export " + far + " --format thr -o " + sc.path("far2.thr")}) {
    SCOPED_TRACE(cmd);
    const CliResult r = run_cli(cmd + " --machine " + kTable);
    expect_one_line_error(r, "far.thr: the pattern turns the arm 1.59e+08 times: at least 3.18e+12 angular steps");
  }
  // the same pattern named by a job file's [contour] kind = "theta-rho" is refused by the digitizer, naming the job
  const std::string far_job = sc.write("far.toml", "[machine]\nfile = \"" + kTable + "\"\n[contour]\nkind = \"theta-rho\"\n"
                                       "file = \"far.thr\"\n[motion]\nspeed = \"40 mm/s\"\n");
  expect_one_line_error(run_cli("digitize " + far_job + " -o " + sc.path("far3.tape")),
                        "far.toml: the pattern turns the arm 1.59e+08 times: at least 3.18e+12 angular steps");
  EXPECT_FALSE(std::filesystem::exists(sc.path("far3.tape")));
  // 1e5 rad (15 915 turns, 3.18e8 steps) is within the bound: check counts it without digitizing
  EXPECT_EQ(cli_json("check " + sc.write("near.thr", "0 0\n1e5 0.5\n") + " --json").value("vertices", 0), 2);
}

TEST(Patterns, CheckCountsWhatIsInThePatternAndFixesIt) {
  Scratch sc;
  // 6 points, one repeat, the centre touched once inside, starting at the centre and ending at the rim
  const std::string file = sc.write("c.thr", "# a comment\r\n0 0\r\n\r\n1 0.5\r\n1 0.5\r\n2 0\r\n4 0.25  # trailing\r\n6 1\r\n");
  const json j = cli_json("check " + file + " --json");
  EXPECT_EQ(j.value("points", 0), 6);
  EXPECT_EQ(j.value("repeated_points", 0), 1);
  EXPECT_EQ(j.value("vertices", 0), 5);
  EXPECT_EQ(j.value("centre_touches", -1), 1);
  EXPECT_EQ(j.value("starts_at", ""), "centre");
  EXPECT_EQ(j.value("ends_at", ""), "rim");
  EXPECT_DOUBLE_EQ(j.value("theta_max_rad", 0.0), 6.0);
  // length in table radii: the spirals from the pole (0,0)-(1,0.5) and (1,0.5)-(2,0), then (2,0)-(4,0.25),
  // (4,0.25)-(6,1), by the closed form of the Archimedean spiral r = b phi from its pole, L = b/2 (phi sqrt(1 +
  // phi^2) + asinh phi), and for the last one by the difference of that form between phi = 1/3 and 4/3 (b = 3/4)
  auto pole_arc = [](double b, double phi) { return 0.5 * b * (phi * std::sqrt(1 + phi * phi) + std::asinh(phi)); };
  const double expected = 2 * pole_arc(0.5, 1.0) + pole_arc(0.125, 2.0) + (pole_arc(0.375, 8.0 / 3) - pole_arc(0.375, 2.0 / 3));
  EXPECT_NEAR(j.value("length_radii", 0.0), expected, 1e-12);
  // on the machine: the time at the speed
  const json m = cli_json("check " + file + " --machine " + kTable + " --speed \"10 mm/s\" --json");
  EXPECT_GT(m.value("duration_s", 0.0), expected * kRadius / 0.010);  // the arm's turn at the centre adds time
  const std::string clean = sc.path("clean.thr");
  cli_json("check " + file + " --fix -o " + clean + " --json");
  const json k = cli_json("check " + clean + " --json");
  EXPECT_EQ(k.value("repeated_points", -1), 0);
  EXPECT_EQ(k.value("vertices", 0), 5);
  EXPECT_NEAR(k.value("length_radii", 0.0), expected, 1e-12);
}

TEST(Patterns, PreviewDrawsThePatternAndItsTape) {
  Scratch sc;
  const std::vector<Vertex> v = {{0.5, 0.8}, {0.5, 0.0}, {0.5 + M_PI, 0.0}, {0.5 + M_PI, 0.8}, {8.0, 0.6}};
  const std::string file = sc.write("p.thr", thr_text(v)), png = sc.path("p.png"), svg = sc.path("t.svg"),
                    tape = sc.path("p.tape");
  const json j = cli_json("preview " + file + " --machine " + kTable + " --speed \"40 mm/s\" -o " + png + " --json");
  EXPECT_EQ(read_file(png).substr(1, 3), "PNG");
  // the ball starts at rho 0.8 on theta 0.5 and ends at rho 0.6 on theta 8 (to within a radial step)
  EXPECT_NEAR(j["start_mm"][0].get<double>(), 160 * std::cos(0.5), 0.02);
  EXPECT_NEAR(j["end_mm"][1].get<double>(), 120 * std::sin(8.0), 0.02);
  // the half turn at the centre is drawn slowed (the arm at its top speed)
  EXPECT_GE(j.value("slowed_stretches", 0), 1);
  cli_json("digitize " + file + " --machine " + kTable + " --speed \"40 mm/s\" -o " + tape + " --json");
  const json t = cli_json("preview " + tape + " -o " + svg + " --json");
  EXPECT_EQ(t.value("steps", 0), j.value("steps", -1));
  EXPECT_NEAR(t["end_mm"][0].get<double>(), j["end_mm"][0].get<double>(), 0.02);  // the coupling is undone
  EXPECT_NE(read_file(svg).find("<svg"), std::string::npos);
  expect_one_line_error(run_cli("preview " + file + " --machine " + kTable + " --speed \"40 mm/s\" -o " + sc.path("p.jpg")), "-o");
}

TEST(Patterns, AnSvgDrawingIsCentredScaledToTheTableAndItsContoursJoined) {
  // the example logo: a ring, the P's outline and counter, and the C: four contours, joined into one path
  const json j = cli_json(digitize_args(kSource + "/examples/patterns/logo.svg"));
  EXPECT_EQ(j.value("contours", 0), 4);
  // scaled so that the drawing's box fits the 200 mm table with 2 % to spare: nothing beyond 196 mm
  EXPECT_LE(j.value("r_max_path_m", 1.0), 0.196 + 1e-9);
  EXPECT_GT(j.value("r_max_path_m", 0.0), 0.100);
  // the same drawing exported as a theta-rho file and read back draws the same steps (the file holds the vertices)
  Scratch sc;
  const std::string thr = sc.path("logo.thr");
  cli_json("export " + kSource + "/examples/patterns/logo.svg --machine " + kTable + " --format thr -o " + thr + " --json");
  const json k = cli_json(digitize_args(thr));
  EXPECT_NEAR(k.value("steps_total", 0.0), j.value("steps_total", 0.0), 4.0);
}

TEST(Patterns, TheCartesianMachinesStepAThetaRhoPatternAndACoupledArmIsNamed) {
  Scratch sc;
  // the sand table without its coupling: a polar machine the comparison can measure
  const std::string plain = sc.write("plain.toml", "[machine]\nscrew_lead = \"40 mm\"\nradial_motor_steps_per_rev = 200\n"
                                                   "radial_microstepping = 16\nangular_steps_per_rev = 20000\n"
                                                   "r_max = \"200 mm\"\n");
  const std::string rose = kSource + "/examples/patterns/rose.thr";
  // the rose crosses the x axis at 190 mm, where y is rounded at the size of x (it failed as "not smooth")
  const json d = cli_json("dda " + rose + " --machine " + plain + " --speed \"40 mm/s\" --method exact --json");
  EXPECT_GT(d.value("steps_total", 0), 100000);
  cli_json("compare " + rose + " --machine " + plain + " --speed \"40 mm/s\" --method exact --json");
  expect_one_line_error(run_cli("compare " + rose + " --machine " + kTable + " --speed \"40 mm/s\" --json"), "coupled");
  cli_json("digitize " + rose + " --machine " + kTable + " --speed \"40 mm/s\" -o " + sc.path("x.tape") + " --json");
  expect_one_line_error(run_cli("error " + sc.path("x.tape") + " --job " + rose + " --machine " + kTable), "coupled");
}

// Where the speed does not enter the result (an export to .thr or SVG, the error metrics, a pole search for the
// least area error), a pattern needs no --speed and a --speed given is refused rather than ignored; the files are
// the same bytes as when one was needed. G-code, which carries the speed, still needs it.
TEST(Patterns, TheSpeedIsAskedForOnlyWhereItEntersTheResult) {
  Scratch sc;
  const std::string star = kSource + "/examples/patterns/star.thr";
  for (const char* format : {"thr", "svg"}) {
    SCOPED_TRACE(format);
    const std::string out = sc.path(std::string("s.") + format);
    ASSERT_EQ(run_cli("export " + star + " --machine " + kTable + " --format " + format + " -o " + out).code, 0);
    expect_one_line_error(run_cli("export " + star + " --machine " + kTable + " --speed \"40 mm/s\" --format " + format +
                                  " -o " + sc.path(std::string("t.") + format)),
                          "--speed: does not enter what this command computes");
  }
  expect_one_line_error(run_cli("export " + star + " --machine " + kTable + " --format gcode -o " + sc.path("s.gcode")),
                        "a pattern file needs the speed along it");
  // a job file's own speed is kept; an override that nothing would use is refused the same way
  const std::string circle = kSource + "/examples/circle.toml";
  ASSERT_EQ(run_cli("digitize " + circle + " -o " + sc.path("c.tape")).code, 0);
  EXPECT_EQ(run_cli("error " + sc.path("c.tape") + " --job " + circle).code, 0);
  expect_one_line_error(run_cli("error " + sc.path("c.tape") + " --job " + circle + " --speed \"2 cm/s\""),
                        "--speed: does not enter");
}

}  // namespace tu_cli_test_cli_patterns
