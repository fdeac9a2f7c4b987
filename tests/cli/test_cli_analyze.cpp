// End-to-end tests of `polarcam analyze` and `polarcam motor fit`: the verdict and its exit status, the JSON
// fields, the CSV and plot, determinism, the speed the verdict offers actually passing, and bad input (one line
// naming the file and key, exit status 2, no output file).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/cli_runner.hpp"
#include "tests/dynamics_helpers.hpp"

namespace tu_cli_test_cli_analyze {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;

namespace {

// The circle of Fig. 5.4 ground at Table 5.1's conditions (examples/ch5/circle.toml).
const std::string kCircle = cli_job("grinding_circle.toml");

void expect_bad(const Scratch& sc, const std::string& job_text, const std::string& must_mention,
                const std::string& extra = "") {
  expect_bad_job(sc, "analyze", "--csv", "csv", job_text, extra, must_mention, ".toml");
}

}  // namespace

TEST(CliAnalyze, GrindingCircleIsNoGoAndTheOfferedSpeedPasses) {
  Scratch sc;
  const std::string job = sc.write("circle.toml", kCircle);
  CliResult r = run_cli("analyze " + job + " --json");
  ASSERT_EQ(r.code, 1) << r.err;  // NO-GO
  const json j = json::parse(r.out);
  EXPECT_EQ(j["verdict"], "NO-GO");
  EXPECT_EQ(j["failing_axis"], "radial");
  EXPECT_EQ(j["failure"], "torque");
  for (const char* axis : {"radial", "angular"})
    for (const char* k : {"max_torque_ratio", "theta_at_max_rad", "max_torque_Nm", "pullout_at_max_Nm",
                          "max_step_rate_hz", "torque_at_max_Nm", "step_rate_at_max_hz"})
      EXPECT_TRUE(j[axis][k].is_number()) << axis << "." << k;
  const double ratio = j["radial"]["max_torque_ratio"];
  EXPECT_GT(ratio, 1.0);
  EXPECT_NEAR(std::abs(j["radial"]["torque_at_max_Nm"].get<double>()) / j["radial"]["pullout_at_max_Nm"].get<double>(),
              ratio, 1e-12 * ratio);
  EXPECT_NEAR(j["margin"].get<double>(), 1.0 / ratio - 1.0, 1e-12);
  EXPECT_NEAR(j["where"]["theta_rad"].get<double>(), j["radial"]["theta_at_max_rad"].get<double>(), 1e-15);
  // the thesis's arm extremes (1.318, 1.823 rad) bound theta; the place is on the circle (radius 5.08 cm)
  const double th = j["where"]["theta_rad"];
  EXPECT_GT(th, 1.31);
  EXPECT_LT(th, 1.83);
  EXPECT_NEAR(std::hypot(j["where"]["point_m"][0].get<double>(), j["where"]["point_m"][1].get<double>()), 0.0508, 1e-9);
  const double v = j["max_passing_speed_mps"];
  EXPECT_LT(v, 0.0152);
  EXPECT_GT(v, 0.005);
  // at the speed offered the job passes; a little faster it does not
  char s1[64], s2[64];
  std::snprintf(s1, sizeof s1, "\"%.9g m/s\"", v);
  std::snprintf(s2, sizeof s2, "\"%.9g m/s\"", v * 1.001);
  EXPECT_EQ(run_cli("analyze " + job + " --speed " + s1).code, 0);
  EXPECT_EQ(run_cli("analyze " + job + " --speed " + s2).code, 1);
  // the text summary says the same
  CliResult t = run_cli("analyze " + job);
  EXPECT_EQ(t.code, 1);
  EXPECT_NE(t.out.find("NO-GO: the radial axis"), std::string::npos) << t.out;
  // at 0.51 cm/s it is GO (Sec. 5.5.2)
  CliResult slow = run_cli("analyze " + job + " --speed \"0.51 cm/s\" --json");
  EXPECT_EQ(slow.code, 0) << slow.err;
  EXPECT_EQ(json::parse(slow.out)["verdict"], "GO");
  // and a safety factor of 2 turns a ratio of ~0.5 into NO-GO
  const double r_slow = json::parse(slow.out)["radial"]["max_torque_ratio"];
  EXPECT_EQ(run_cli("analyze " + job + " --speed \"0.51 cm/s\" --safety-factor " + std::to_string(1.01 / r_slow)).code,
            1);
  EXPECT_EQ(run_cli("analyze " + job + " --speed \"0.51 cm/s\" --safety-factor " + std::to_string(0.99 / r_slow)).code,
            0);
}

TEST(CliAnalyze, CsvAndPlotAgreeWithTheSummaryAndRepeatExactly) {
  Scratch sc;
  const std::string job = sc.write("circle.toml", kCircle);
  CliResult r = run_cli("analyze " + job + " --json --csv " + sc.path("a.csv") + " --plot " + sc.path("a.png"));
  ASSERT_EQ(r.code, 1) << r.err;
  const json j = json::parse(r.out);
  std::ifstream in(sc.path("a.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("s_m,t_s,theta_rad,r_m,x_m,y_m,", 0), 0u) << line;
  std::vector<std::string> cols;
  {
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cols.push_back(c);
  }
  const size_t ir = std::find(cols.begin(), cols.end(), "ratio_radial") - cols.begin();
  ASSERT_LT(ir, cols.size());
  size_t rows = 0;
  double max_ratio = 0.0, last_s = -1.0;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) v.push_back(std::stod(c));
    ASSERT_EQ(v.size(), cols.size());
    ASSERT_GE(v[0], last_s);  // along the path
    last_s = v[0];
    max_ratio = std::max(max_ratio, std::abs(v[ir]));
    ++rows;
  }
  EXPECT_EQ(rows, j["samples"].get<size_t>());
  const double m = j["radial"]["max_torque_ratio"];
  EXPECT_LE(max_ratio, m * (1 + 1e-9));
  EXPECT_GE(max_ratio, m * 0.999);
  const std::string png = read_file(sc.path("a.png"));
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  // same job, same bytes
  CliResult r2 = run_cli("analyze " + job + " --json --csv " + sc.path("b.csv") + " --plot " + sc.path("b.png"));
  EXPECT_EQ(r.out, r2.out);
  EXPECT_EQ(read_file(sc.path("a.csv")), read_file(sc.path("b.csv")));
  EXPECT_EQ(png, read_file(sc.path("b.png")));
}

TEST(CliAnalyze, SeveralSpeedsAndMasses) {
  Scratch sc;
  const std::string job = sc.write("circle.toml", kCircle);
  const json j = cli_json("analyze " + job +
                        " --json --mass \"14.6 kg\" --mass \"43.8 kg\" --speed \"0.51 cm/s\" "
                        "--speed \"1.51 cm/s\" --plot " +
                        sc.path("f.svg") + " --csv " + sc.path("f.csv"));
  ASSERT_EQ(j["cases"].size(), 4u);
  EXPECT_EQ(j["verdict"], "GO");
  for (const auto& c : j["cases"]) EXPECT_EQ(c["load"]["kind"], "inertial");
  // the radial ratio scales with the carriage's whole mass (Eq. 6.1): (0.9 + 43.8) / (0.9 + 14.6)
  const double r1 = j["cases"][0]["radial"]["max_torque_ratio"], r2 = j["cases"][1]["radial"]["max_torque_ratio"];
  EXPECT_NEAR(r2 / r1, 44.7 / 15.5, 1e-9);
  // and rises with speed
  EXPECT_GT(j["cases"][2]["radial"]["max_torque_ratio"].get<double>(), r1);
  EXPECT_NE(read_file(sc.path("f.svg")).find("<svg"), std::string::npos);
  const std::string csv = read_file(sc.path("f.csv"));
  EXPECT_EQ(csv.rfind("case,s_m,", 0), 0u);
  // cases numbered from 1 in the CSV and in the text alike
  EXPECT_EQ(csv.substr(csv.find('\n') + 1, 2), "1,");
  EXPECT_NE(csv.find("\n4,"), std::string::npos);
  EXPECT_EQ(csv.find("\n0,"), std::string::npos);
  const CliResult text = run_cli("analyze " + job + " --mass \"14.6 kg\" --mass \"43.8 kg\" --speed \"0.51 cm/s\" --speed \"1.51 cm/s\"");
  EXPECT_NE(text.out.find("  case 1 of 4\n"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("  case 4 of 4\n"), std::string::npos);
  EXPECT_EQ(text.out.find("case 0"), std::string::npos);
}

TEST(CliAnalyze, TheLoadDoesNotChangeTheTape) {
  Scratch sc;
  const std::string with = sc.write("with.toml", kCircle);
  std::string bare = kCircle;
  bare = bare.substr(0, bare.find("[load]"));
  const std::string without = sc.write("without.toml", bare);
  ASSERT_EQ(run_cli("digitize " + with + " -o " + sc.path("a.tape")).code, 0);
  ASSERT_EQ(run_cli("digitize " + without + " -o " + sc.path("b.tape")).code, 0);
  EXPECT_EQ(read_file(sc.path("a.tape")), read_file(sc.path("b.tape")));
}

TEST(CliAnalyze, BadInputGivesOneClearLine) {
  Scratch sc;
  expect_bad(sc, replace(kCircle, "c1 = 1.66", "c1 = 1.66\nfoo = 2"), "unknown key 'load.foo'");
  expect_bad(sc, replace(kCircle, "kind = \"grinding\"", "kind = \"turning\""), "load.kind");
  expect_bad(sc, replace(kCircle, "depth = \"0.001 in\"\n", ""), "'depth' is missing");
  expect_bad(sc, replace(kCircle, "k_c = \"6.46e7 kN/m^2\"", "k_c = \"6.46e7 kN\""), "load.k_c");
  expect_bad(sc, replace(kCircle, "safety_factor = 1.0", "safety_factor = 0.5"), "limits.safety_factor");
  expect_bad(sc, replace(kCircle, "[limits]", "[limits]\nmargin = 3"), "unknown key 'limits.margin'");
  expect_bad(sc,
             replace(kCircle, "file = \"machines/fahim1983.toml\"",
                     "file = \"machines/fahim1983.toml\"\ncarriage_mass = \"-1 kg\""),
             "machine.carriage_mass");
  expect_bad(sc, replace(kCircle, "file = \"machines/fahim1983.toml\"", "file = \"machines/fahim1983.toml\"\nworm = 3"),
             "machine.worm");
  expect_bad(sc, replace(kCircle, "[contour]", "[machine.radial_motor]\nmodel = \"magic\"\n[contour]"),
             "radial_motor.model");
  expect_bad(sc, replace(kCircle, "[contour]", "[machine.motor]\ntorque_constant = \"0.0759 N m\"\n[contour]"),
             "machine.motor.torque_constant");
  expect_bad(sc, replace(kCircle, "[contour]", "[machine.motor]\nwinding = 2\n[contour]"),
             "unknown key 'machine.motor.winding'");
  expect_bad(sc, replace(kCircle, "[contour]", "[machine.angular_motor]\nsteps_per_rev = 400\n[contour]"),
             "'machine.angular_motor.steps_per_rev' does not apply to a motor of model \"electrical\"");
  // a tabulated curve that stops short of the radial motor's step rate: named, not extrapolated
  expect_bad(sc,
             replace(kCircle, "[contour]",
                     "[machine.radial_motor]\nmodel = \"curve\"\nsteps_per_rev = 400\n"
                     "pullout_curve = [[\"0 Hz\", \"0.33 N m\"], [\"1000 Hz\", \"0.3 N m\"], [\"2000 Hz\", \"0.25 N "
                     "m\"]]\n[contour]"),
             "radial motor: step rate");
  expect_bad(sc,
             replace(kCircle, "[contour]",
                     "[machine.radial_motor]\nmodel = \"curve\"\nsteps_per_rev = 400\n"
                     "pullout_curve = [[\"0 Hz\", \"0.33 N m\"], [\"0 Hz\", \"0.3 N m\"]]\n[contour]"),
             "radial_motor.pullout_curve");
  expect_bad(sc, replace(kCircle, "kind = \"grinding\"", "kind = \"force\"\ntangential = \"3 N\""),
             "unknown key 'load.");
  {
    CliResult r = run_cli("analyze " + sc.write("ok.toml", kCircle) + " --mass \"1 kg\" --depth \"0.1 mm\"");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("--mass or --depth"), std::string::npos) << r.err;
  }
  expect_bad(sc, kCircle, "samples along", "--spacing \"1 nm\"");
  // a machine without dynamics
  sc.write("machines/bare.toml", "[machine]\nradial_resolution = \"0.001 in\"\nangular_steps_per_rev = 16000\n");
  expect_bad(sc, replace(kCircle, "machines/fahim1983.toml", "machines/bare.toml"), "no dynamics");
}

TEST(CliAnalyze, TabulatedCurveCoveringTheRatesIsUsed) {
  Scratch sc;
  // the prototype's motor as a datasheet would tabulate it, up to 6 kHz: the verdict matches the model's closely
  std::string curve = "pullout_curve = [";
  const auto m = polarcam::test::thesis_motor();
  for (int f = 0; f <= 6000; f += 250) {
    char row[96];
    std::snprintf(row, sizeof row, "%s[\"%d Hz\", \"%.9g N m\"]", f ? ", " : "", f, m.pullout_at_rate(f));
    curve += row;
  }
  curve += "]\n";
  const std::string job = sc.write(
      "curve.toml",
      replace(kCircle, "[contour]", "[machine.motor]\nmodel = \"curve\"\nsteps_per_rev = 400\n" + curve + "[contour]"));
  CliResult a = run_cli("analyze " + job + " --json");
  CliResult b = run_cli("analyze " + sc.write("model.toml", kCircle) + " --json");
  ASSERT_EQ(a.code, 1) << a.err;
  ASSERT_EQ(b.code, 1) << b.err;
  const double ra = json::parse(a.out)["radial"]["max_torque_ratio"],
               rb = json::parse(b.out)["radial"]["max_torque_ratio"];
  EXPECT_NEAR(ra, rb, 1e-3 * rb);
}

TEST(CliMotorFit, RecoversTheThesisMotor) {
  Scratch sc;
  const auto m = polarcam::test::thesis_motor();
  std::string csv = "step_rate_hz,torque_Nm\n# measured\n";
  for (int f = 0; f <= 10000; f += 500) {
    double t = m.pullout_at_rate(f);
    if (f == 3000) t *= 0.7;  // a bad reading
    char row[64];
    std::snprintf(row, sizeof row, "%d,%.12g\n", f, t);
    csv += row;
  }
  const std::string pts = sc.write("points.csv", csv);
  const json j = cli_json("motor fit " + pts +
                        " --supply-voltage \"24 V\" --resistance \"6.5 ohm\" --rotor-teeth 50 --json --plot " +
                        sc.path("fit.png"));
  EXPECT_NEAR(j["fitted"]["torque_constant_NmpA"].get<double>(), 0.0759, 1e-4 * 0.0759);
  EXPECT_NEAR(j["fitted"]["voltage_constant_Vsprad"].get<double>(), 0.068, 1e-3 * 0.068);
  EXPECT_NEAR(j["fitted"]["inductance_H"].get<double>(), 6.3e-4, 1e-4 * 6.3e-4);
  ASSERT_EQ(j["outliers"].size(), 1u);
  EXPECT_EQ(j["outliers"][0], 7);  // 1-based: the point at 3000 Hz
  EXPECT_EQ(j["residuals"].size(), 21u);
  EXPECT_EQ(read_file(sc.path("fit.png")).substr(1, 3), "PNG");
  // the known constants can come from the machine file instead
  CliResult r2 = run_cli("motor fit " + pts + " --machine " + sc.path("machines/fahim1983.toml") + " --json");
  ASSERT_EQ(r2.code, 0) << r2.err;
  EXPECT_EQ(json::parse(r2.out)["fitted"], j["fitted"]);
  // bad input
  CliResult bad = run_cli("motor fit " + sc.write("bad.csv", "0,0.3\n100,abc\n") + " --machine " +
                          sc.path("machines/fahim1983.toml"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("bad.csv:2"), std::string::npos) << bad.err;
  CliResult nov = run_cli("motor fit " + pts);
  EXPECT_EQ(nov.code, 2);
  EXPECT_NE(nov.err.find("--supply-voltage"), std::string::npos) << nov.err;
  // options that another makes moot are refused rather than ignored
  expect_one_line_error(run_cli("motor fit " + pts + " --supply-voltage \"24 V\" --resistance \"6.5 ohm\" --rotor-teeth 50 --axis angular"),
                        "--axis requires --machine");
  expect_one_line_error(run_cli("motor fit " + pts + " --machine " + sc.path("machines/fahim1983.toml") +
                                " --loss none --loss-scale \"0.0001 N m\""),
                        "--loss-scale: scales a robust loss");
}

TEST(CliAnalyze, StepRateLimitIsNamedAndTheSpeedFollowsFromIt) {
  // without load the circle's torques are tiny, but at 2 cm/s the radial motor must step faster than its 5500 Hz:
  // the radial speed peaks at V where the tangent points along the arm, so the limit is
  // V = 5500 / (k_R * 400) = 5500 / (787.40 rev/m * 400) = 1.7462 cm/s
  Scratch sc;
  std::string bare = kCircle;
  bare = bare.substr(0, bare.find("[load]"));
  const std::string job = sc.write("fast.toml", replace(bare, "speed = \"1.52 cm/s\"", "speed = \"2 cm/s\""));
  CliResult r = run_cli("analyze " + job + " --json");
  ASSERT_EQ(r.code, 1) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["failing_axis"], "radial");
  EXPECT_EQ(j["failure"], "step_rate");
  EXPECT_EQ(j["radial"]["failure"], "step_rate");
  EXPECT_LT(j["radial"]["max_torque_ratio"].get<double>(), 0.1);
  const double k_R = 1.0 / (0.05 * 0.0254);
  EXPECT_NEAR(j["radial"]["max_step_rate_hz"].get<double>(), k_R * 0.02 * 400, 1e-6 * k_R * 0.02 * 400);
  const double v = j["max_passing_speed_mps"];
  EXPECT_LE(v, 5500 / (k_R * 400));
  EXPECT_GT(v, 5500 / (k_R * 400) * (1 - 2e-4));
}

}  // namespace tu_cli_test_cli_analyze
