// End to end: the template digitizer's speed ([motion] speed_profile = "template", Fahim Sec. 3.5) on a circle
// and a straight line, measured from the tape; the template-speed command; bad keys refused in one line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_template {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInch = 0.0254;

// The circle of radius 2 in about (0, 0), its centre 8 in from the machine pole; the tool centre (the driven
// roller's centre) 1/16 in outside it or inside it.
std::string circle_job(const std::string& side, const std::string& extra = "") {
  return "[machine]\nfile = \"machines/fahim1983.toml\"\n"
         "[contour]\nkind = \"circle\"\nradius = \"2 in\"\n"
         "[placement]\nC = \"20.32 cm\"\nbeta = \"3*pi/2 rad\"\n"
         "[tool]\nradius = \"1/16 in\"\nside = \"" + side + "\"\n"
         "[motion]\nspeed = \"1.52 cm/s\"\nspeed_profile = \"template\"\n" + extra +
         "[template]\nthickness = \"1/8 in\"\nroller_radius = \"1/16 in\"\nside = \"" + side + "\"\n";
}

// Duration of a tape from its header (inspect --json) and the time of its last step (inspect --csv).
struct TapeTimes {
  double duration_s = 0, last_step_s = 0;
  long steps = 0;
};
TapeTimes tape_times(const std::string& tape) {
  TapeTimes t;
  const json h = cli_json("inspect " + tape + " --json");
  t.duration_s = h["duration_s"].get<double>();
  const CliResult c = run_cli("inspect " + tape + " --csv");
  EXPECT_EQ(c.code, 0) << c.err;
  std::istringstream in(c.out);
  std::string line;
  std::getline(in, line);
  long long last = 0;
  while (std::getline(in, line)) {
    long long ns = 0;
    if (std::sscanf(line.c_str(), "%lld,", &ns) == 1) last = ns;
    ++t.steps;
  }
  t.last_step_s = static_cast<double>(last) * 1e-9;
  return t;
}

}  // namespace

TEST(CliTemplate, CircleTapeMeanSpeedIsTheCorrectedEquation33) {
  const double H = kInch / 8, Rr = kInch / 16, R = 2 * kInch, Vt = 0.0152;
  const double rho = R / H, rr = Rr / H;  // 16, 1/2
  // outside: the centre of curvature is on the other side of the template (3.3b); inside: on the roller's (3.3a)
  const double v_out = Vt * 2 * (rho + rr) / (2 * rho - 1), v_in = Vt * 2 * (rho - rr) / (2 * rho + 1);
  Scratch sc;
  for (const auto& [side, v, tool_radius] : {std::tuple{std::string("outside"), v_out, R + Rr},
                                             std::tuple{std::string("inside"), v_in, R - Rr}}) {
    SCOPED_TRACE(side);
    const std::string job = sc.write("c.toml", circle_job(side)), tape = sc.path("c.tape");
    const json s = cli_json("digitize " + job + " -o " + tape + " --json");
    const TapeTimes tt = tape_times(tape);
    ASSERT_GT(tt.steps, 10000);
    // the tool centre's circle, whole, over the tape's duration
    const double length = 2 * kPi * tool_radius;
    EXPECT_NEAR(length / tt.duration_s, v, 1e-3 * v);
    EXPECT_NEAR(length / tt.duration_s, v, 1e-9 * v);  // in fact exact to the nanosecond rounding
    // the same from the steps alone: the last step comes within one step's time of the end
    EXPECT_NEAR(length / tt.last_step_s, v, 1e-3 * v);
    // the summary
    const json& t = s["template_speed"];
    EXPECT_NEAR(t["speed_min_mps"].get<double>(), v, 1e-9 * v);
    EXPECT_NEAR(t["speed_max_mps"].get<double>(), v, 1e-9 * v);
    EXPECT_NEAR(t["worst"]["radius_of_curvature_m"].get<double>(), R, 1e-9);
    EXPECT_EQ(t["worst"]["centre_of_curvature"], side == "outside" ? "other_side" : "roller_side");
    EXPECT_EQ(t["set_speed_mps"].get<double>(), Vt);
    EXPECT_NEAR(s["path_length_m"].get<double>(), length, 1e-12);
  }
}

TEST(CliTemplate, StraightTemplateRunsAtTheSetSpeed) {
  Scratch sc;
  const std::string text =
      "[machine]\nfile = \"machines/fahim1983.toml\"\n"
      "[contour]\nkind = \"line\"\nfrom = [\"-5 cm\", \"15 cm\"]\nto = [\"6 cm\", \"22 cm\"]\n"
      "[motion]\nspeed = \"1 cm/s\"\nspeed_profile = \"template\"\n"
      "[template]\nthickness = \"3 mm\"\nroller_radius = \"2 mm\"\nside = \"right\"\n";
  const std::string job = sc.write("l.toml", text), tape = sc.path("l.tape");
  const json s = cli_json("digitize " + job + " -o " + tape + " --json");
  const double length = std::hypot(0.11, 0.07);
  const TapeTimes tt = tape_times(tape);
  EXPECT_NEAR(length / tt.duration_s, 0.01, 1e-3 * 0.01);
  EXPECT_NEAR(length / tt.duration_s, 0.01, 1e-9 * 0.01);
  EXPECT_EQ(s["template_speed"]["v_star_min"].get<double>(), 1.0);
  EXPECT_EQ(s["template_speed"]["v_star_max"].get<double>(), 1.0);
  EXPECT_TRUE(s["template_speed"]["worst"]["radius_of_curvature_m"].is_null());
}

TEST(CliTemplate, ExampleJobDigitizes) {
  const json s = cli_json("digitize " + std::string(POLARCAM_SOURCE_DIR) + "/examples/template-circle.toml --json");
  EXPECT_NEAR(s["template_speed"]["v_star_max"].get<double>(), 33.0 / 31.0, 1e-9);
}

TEST(CliTemplate, BadKeysAreRefusedInOneLine) {
  Scratch sc;
  auto bad = [&](const std::string& text, const std::string& mention) {
    expect_bad_job(sc, "digitize", "-o", "tape", text, "", mention);
  };
  const std::string good = circle_job("outside");
  bad(replace(good, "speed_profile = \"template\"", "speed_profile = \"templet\""), "motion.speed_profile");
  bad(replace(good, "thickness = \"1/8 in\"\n", ""), "'thickness' is missing");
  bad(replace(good, "thickness = \"1/8 in\"", "thickness = \"0 in\""), "template.thickness");
  bad(replace(good, "roller_radius = \"1/16 in\"", "roller_radius = \"1/16 kg\""), "template.roller_radius");
  bad(replace(good, "side = \"outside\"\n", "side = \"outside\"\nwidth = \"1 in\"\n"), "width");
  bad(replace(good, "speed_profile = \"template\"\n", ""), "[template]");
  bad(replace(good, "speed_profile = \"template\"\n", "speed_profile = \"template\"\naccel = \"1 cm/s^2\"\n"), "accel");
  // inside a 2 in circle with rollers of 2.5 in radius: the driven roller cannot turn that tightly
  bad(replace(replace(circle_job("inside"), "roller_radius = \"1/16 in\"", "roller_radius = \"2.5 in\""),
              "radius = \"1/16 in\"", "radius = \"0 in\""),
      "roller stops");
  // the [template] section of an open contour names a side of travel, not inside or outside
  bad("[machine]\nfile = \"machines/fahim1983.toml\"\n[contour]\nkind = \"line\"\nfrom = [\"0 cm\", \"15 cm\"]\n"
      "to = [\"6 cm\", \"22 cm\"]\n[motion]\nspeed = \"1 cm/s\"\nspeed_profile = \"template\"\n"
      "[template]\nthickness = \"3 mm\"\nroller_radius = \"2 mm\"\nside = \"inside\"\n",
      "template.side");
  // the DDA cannot follow a varying speed
  const std::string job = sc.write("c.toml", good);
  expect_one_line_error(run_cli("dda " + job), "template");
}

TEST(CliTemplate, TemplateSpeedCommandTabulatesAndDrawsFigure32) {
  Scratch sc;
  const std::string png = sc.path("fig32.png");
  const json j = cli_json("template-speed --thickness \"1/8 in\" --roller-radius \"1/16 in\" --roller-radius \"1/8 in\" "
                          "--radius-of-curvature \"5 cm\" --plot " + png + " --json");
  ASSERT_EQ(j["rollers"].size(), 2u);
  const double rho = 0.05 / (kInch / 8);
  const json& p = j["rollers"][0]["points"][0];
  EXPECT_NEAR(p["rho_star"].get<double>(), rho, 1e-12);
  EXPECT_NEAR(p["v_star_roller_side"].get<double>(), 2 * (rho - 0.5) / (2 * rho + 1), 1e-12);
  EXPECT_NEAR(p["v_star_other_side"].get<double>(), 2 * (rho + 0.5) / (2 * rho - 1), 1e-12);
  // the thesis's example: under 10 % on both sides
  EXPECT_LT(std::abs(p["v_star_roller_side"].get<double>() - 1), 0.1);
  EXPECT_LT(std::abs(p["v_star_other_side"].get<double>() - 1), 0.1);
  EXPECT_NEAR(j["rollers"][1]["points"][0]["v_star_roller_side"].get<double>(), 2 * (rho - 1) / (2 * rho + 1), 1e-12);
  const std::string bytes = read_file(png);
  ASSERT_GT(bytes.size(), 1000u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  // a radius the rollers cannot follow on the other side is null, not a number
  const json k = cli_json("template-speed --thickness \"3 mm\" --roller-radius \"1 mm\" --radius-of-curvature \"3.5 mm\" --json");
  EXPECT_TRUE(k["rollers"][0]["points"][0]["v_star_other_side"].is_null());
  EXPECT_NEAR(k["rollers"][0]["points"][0]["v_star_roller_side"].get<double>(), 2 * (3.5 / 3 - 1.0 / 3) / (7.0 / 3 + 1), 1e-12);
  expect_one_line_error(run_cli("template-speed --thickness \"0 mm\" --roller-radius \"1 mm\""), "--thickness");
  expect_one_line_error(run_cli("template-speed --thickness \"3 mm\" --roller-radius \"1 kg\""), "--roller-radius");
  // the plot's axis without a plot would be ignored
  expect_one_line_error(run_cli("template-speed --thickness \"3 mm\" --roller-radius \"1 mm\" --rho-star-max 20"),
                        "--rho-star-max requires --plot");
}

}  // namespace tu_cli_test_cli_template
