// `polarcam report` of a pattern on a sand table (no dynamics, a coupled arm): the pattern report. The expected
// figures are the pattern's own geometry: examples/patterns/diameters.thr draws 18 diameters of the 200 mm table
// joined by 17 rim arcs of 10 degrees, and crosses the centre 18 times, where the arm turns half a turn at the
// machine's max_angular_speed of 3 rad/s while the ball waits.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_pattern_report {  // the test files of a program compile together (unity build)

using namespace polarcam::test;

namespace {

const std::string kSource = POLARCAM_SOURCE_DIR;
const std::string kTable = kSource + "/examples/machines/sand-table.toml";

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The value cell of the row `name` of the report's tables.
std::string row(const std::string& html, const std::string& name) {
  const std::string key = "<tr><td>" + name + "</td><td>";
  const size_t at = html.find(key);
  if (at == std::string::npos) return "(no row " + name + ")";
  const size_t b = at + key.size();
  return html.substr(b, html.find("</td>", b) - b);
}

}  // namespace

TEST(PatternReport, ASandTablePatternGetsWhatItDrawsAndHowLong) {
  Scratch sc;
  const std::string out = sc.path("r.html");
  const CliResult r = run_cli("report " + kSource + "/examples/patterns/diameters.thr --machine " + kTable +
                              " --speed \"40 mm/s\" -o " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("GO"), std::string::npos);
  const std::string html = slurp(out);
  for (const char* id : {"verdict", "drawing", "time", "tape", "limits"})
    EXPECT_NE(html.find(std::string("id=\"") + id + "\""), std::string::npos) << id;
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
  EXPECT_NE(html.find("verdict go"), std::string::npos);
  // 18 x 400 mm + 17 x 200 mm x pi / 18 = 7793.41 mm
  const double drawn = 18 * 400.0 + 17 * 200.0 * M_PI / 18;
  EXPECT_NEAR(std::stod(row(html, "path length as drawn")), drawn, 0.01);
  // 18 half turns at 3 rad/s: 18 pi / 3 = 18.85 s
  EXPECT_NEAR(std::stod(row(html, "time lost where the requested speed is not kept")), 18 * M_PI / 3, 0.01);
  EXPECT_NE(html.find("describes no masses and motors"), std::string::npos);
  EXPECT_NE(html.find("coupled"), std::string::npos);
  // the job report's options have nothing to set in this report: refused rather than ignored
  for (const char* opt : {" --map-size 4", " --max-evaluations 10", " --safety-factor 3"}) {
    SCOPED_TRACE(opt);
    const std::string other = sc.path("other.html");
    expect_one_line_error(run_cli("report " + kSource + "/examples/patterns/diameters.thr --machine " + kTable +
                                  " --speed \"40 mm/s\" -o " + other + opt),
                          "has no pole survey, pole search or torque ratios");
    EXPECT_FALSE(std::filesystem::exists(other));
  }
}

TEST(PatternReport, AMotorTooSlowForThePatternIsNoGoWithTheSpeedThatWouldDo) {
  Scratch sc;
  // the table with dynamics and motors that step at most 200 times a second
  std::string m = slurp(kTable);
  const std::string dyn =
      "carriage_mass = \"0.2 kg\"\narm_inertia = \"0.01 kg m^2\"\narm_friction_torque = \"0.01 N m\"\n"
      "worm_factor = 0.2\nscrew_factor = \"0.01 m\"\n\n[machine.motor]\nmodel = \"electrical\"\n"
      "energisation = \"wave\"\nsupply_voltage = \"24 V\"\ntorque_constant = \"0.0759 N m/A\"\n"
      "voltage_constant = \"0.068 V s/rad\"\nrotor_teeth = 50\nresistance = \"6.5 ohm\"\ninductance = \"6.3e-4 H\"\n"
      "max_step_rate = \"200 Hz\"\n\n";
  m.insert(m.find("[gcode]"), dyn);
  const std::string machine = sc.write("slow.toml", m), out = sc.path("r.html");
  const CliResult r = run_cli("report " + kSource + "/examples/patterns/diameters.thr --machine " + machine +
                              " --speed \"40 mm/s\" -o " + out);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.out.find("NO-GO"), std::string::npos);
  const std::string html = slurp(out);
  EXPECT_NE(html.find("verdict nogo"), std::string::npos);
  EXPECT_NE(html.find("above its limit of 200 Hz"), std::string::npos);
  EXPECT_NE(html.find("Run at"), std::string::npos);
}

}  // namespace tu_cli_test_cli_pattern_report
