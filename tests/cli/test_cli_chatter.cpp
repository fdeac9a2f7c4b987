// polarcam chatter and polarcam identify end to end: the document's systems through the example files, the
// simulation's CSV, the lobes and their figure, refusals of bad input in one line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <vector>

#include "tests/cli_runner.hpp"
#include "tests/scratch.hpp"

namespace polarcam::test {
namespace tu_cli_test_cli_chatter {  // named: the test files compile together

const std::string kExamples = std::string(POLARCAM_SOURCE_DIR) + "/examples/process/";

TEST(CliChatter, ExampleSystemsGiveTheNyquistLimits) {
  // A. B. Dunckley (1978), Sec. 2.2.4.2-2.2.4.3: systems 2 and 4, reproducible within 5 % and 3 %
  const auto j2 = cli_json("chatter " + kExamples + "dunckley-case2.toml --json");
  EXPECT_NEAR(j2["critical_gain"].get<double>(), 230.0, 0.05 * 230.0);
  EXPECT_NEAR(j2["chatter_frequency_rad_s"].get<double>(), 601.0, 0.03 * 601.0);
  const auto j4 = cli_json("chatter " + kExamples + "dunckley-case4.toml --json");
  EXPECT_NEAR(j4["critical_gain"].get<double>(), 40.0, 0.05 * 40.0);
  EXPECT_NEAR(j4["chatter_frequency_rad_s"].get<double>(), 782.0, 0.03 * 782.0);
  EXPECT_LT(j4["simple_criterion"]["critical_gain"].get<double>(), j4["critical_gain"].get<double>());
  EXPECT_EQ(j4["modes"].size(), 2u);
  EXPECT_FALSE(j4.contains("lobes"));
}

TEST(CliChatter, SameInputSameBytes) {
  const auto a = run_cli("chatter " + kExamples + "dunckley-case1.toml --json --lobes --lobe-count 20");
  const auto b = run_cli("chatter " + kExamples + "dunckley-case1.toml --json --lobes --lobe-count 20");
  EXPECT_EQ(a.code, 0);
  EXPECT_EQ(a.out, b.out);
}

TEST(CliChatter, LobesTableAndFigure) {
  Scratch sc;
  const std::string png = sc.path("lobes.png");
  const auto j = cli_json("chatter " + kExamples + "dunckley-case2.toml --json --lobes --lobe-count 21 --spindle-min "
                          "\"200 rpm\" --spindle-max \"400 rpm\" --plot " + png);
  ASSERT_EQ(j["lobes"].size(), 21u);
  EXPECT_DOUBLE_EQ(j["lobes"][0]["spindle_speed_rpm"].get<double>(), 200.0);
  EXPECT_DOUBLE_EQ(j["lobes"][10]["spindle_speed_rpm"].get<double>(), 300.0);
  // 300 rpm is the file's own cut
  EXPECT_NEAR(j["lobes"][10]["critical_gain"].get<double>(), j["critical_gain"].get<double>(), 1e-9);
  const std::string bytes = read_file(png);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
}

TEST(CliChatter, SimulationUnderAndOverTheLimit) {
  const double kc = cli_json("chatter " + kExamples + "dunckley-case2.toml --json")["critical_gain"].get<double>();
  auto sim = [&](double f) {
    return cli_json("chatter " + kExamples + "dunckley-case2.toml --json --simulate " + std::to_string(f * kc))["simulation"];
  };
  const auto under = sim(0.95), over = sim(1.05);
  EXPECT_FALSE(under["growing"].get<bool>());
  EXPECT_TRUE(over["growing"].get<bool>());
  EXPECT_NEAR(over["frequency_rad_s"].get<double>(), 612.7, 0.01 * 612.7);
}

TEST(CliChatter, SimulationCsv) {
  const auto r = run_cli("chatter " + kExamples + "dunckley-case4.toml --simulate 30 --duration \"0.4 s\" --csv");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t_s,x_m_m,x_w_m,force_N");
  int rows = 0;
  double t = -1.0, last_t = 0.0;
  while (std::getline(in, line)) {
    ++rows;
    last_t = std::stod(line.substr(0, line.find(',')));
    EXPECT_GT(last_t, t);
    t = last_t;
  }
  EXPECT_EQ(rows, 801);  // t = 0 and 400 per revolution over two revolutions
  EXPECT_NEAR(last_t, 0.4, 1e-9);
}

TEST(CliChatter, BadInputIsOneLine) {
  Scratch sc;
  const std::string good = read_file(kExamples + "dunckley-case1.toml");
  const std::string bad = sc.write("bad.toml", replace(good, "K_w = 12000", "K_w = \"12 kg\""));
  expect_one_line_error(run_cli("chatter " + bad), "key 'structure.K_w'");
  const std::string unknown = sc.write("unknown.toml", replace(good, "overlap = 1", "overlap = 1\nfeed = 2"));
  expect_one_line_error(run_cli("chatter " + unknown), "unknown key 'cut.feed'");
  expect_one_line_error(run_cli("chatter " + kExamples + "dunckley-case1.toml --csv"), "--csv");
  expect_one_line_error(run_cli("chatter " + kExamples + "dunckley-case1.toml --simulate -3"), "--simulate");
  expect_one_line_error(run_cli("chatter " + kExamples + "dunckley-case1.toml --lobes --spindle-min \"3 m\""),
                        "--spindle-min");
  // the lobes' options without the lobes would be ignored
  for (const char* opt : {" --spindle-min \"150 rpm\"", " --spindle-max \"3000 rpm\"", " --lobe-count 10"})
    expect_one_line_error(run_cli("chatter " + kExamples + "dunckley-case1.toml --json" + opt),
                          "shapes the stability lobes: give --lobes");
  const std::string plot = sc.path("x.gif");
  expect_one_line_error(run_cli("chatter " + kExamples + "dunckley-case1.toml --plot " + plot), "x.gif");
  expect_one_line_error(run_cli("chatter " + sc.path("missing.toml")), "missing.toml");
}

// A structure's response to a random force, written as polarcam's identify reads it: the oscillator stepped in
// closed form with the force held over each sample (w_n 300 rad/s, zeta 0.03, static gain 1e-6 m/N).
std::string response_csv(bool with_force) {
  const double wn = 300.0, zeta = 0.03, gain = 1e-6, dt = 1e-3;
  const double sigma = zeta * wn, wd = wn * std::sqrt(1.0 - zeta * zeta);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> force(0.0, 40.0);
  std::ostringstream os;
  os.precision(17);
  os << (with_force ? "t_s,force_N,displacement_m\n" : "t_s,displacement_m\n");
  double x = with_force ? 0.0 : 1e-4, v = 0.0;
  for (int k = 0; k < 6000; ++k) {
    const double F = with_force ? force(rng) : 0.0;
    os << k * dt;
    if (with_force) os << "," << F;
    os << "," << x << "\n";
    const double xp = F * gain, a = x - xp, b = (v + sigma * a) / wd;
    const double e = std::exp(-sigma * dt), c = std::cos(wd * dt), s = std::sin(wd * dt);
    x = xp + e * (a * c + b * s);
    v = e * (-sigma * (a * c + b * s) + (-a * wd * s + b * wd * c));
  }
  return os.str();
}

TEST(CliChatter, SuppressorHoldsTheCutAndWritesItsSteps) {
  // A. B. Dunckley (1978), Sec. 3.3: system 1 at 3 times its limit chatters without the suppressor and is held with
  // it; the steps file adds up to the final position, the series' tool displacement is whole steps
  Scratch sc;
  const std::string csv = sc.path("run.csv"), steps = sc.path("steps.csv");
  const auto j = cli_json("chatter " + kExamples + "dunckley-suppressor.toml --simulate 1311 --suppress --duration "
                          "\"1 s\" --json --csv " + csv + " --steps-out " + steps);
  const auto& u = j["suppressor"];
  EXPECT_GT(u["without"]["growth_per_revolution"].get<double>(), 2.0);
  EXPECT_TRUE(u["without"]["growing"].get<bool>());
  EXPECT_LT(u["with"]["last_revolution_half_range_relative_m"].get<double>(), 1.5 * 0.00067);
  EXPECT_GT(u["amplitude_reduction"].get<double>(), 100.0);
  EXPECT_FALSE(u["saturated"].get<bool>());
  EXPECT_TRUE(u["first_saturation_s"].is_null());
  EXPECT_LE(u["max_step_rate_used_per_s"].get<double>(), 5000.0);
  EXPECT_EQ(u["model"]["source"], "structure");
  // the plain simulation is the run without the suppressor
  EXPECT_EQ(j["simulation"]["growth_per_revolution"], u["without"]["growth_per_revolution"]);

  std::istringstream in(read_file(steps));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t_s,dir,position_steps");
  long long rows = 0, sum = 0, position = 0;
  double t = -1.0;
  while (std::getline(in, line)) {
    ++rows;
    std::istringstream f(line);
    std::string a, b, c;
    std::getline(f, a, ',');
    std::getline(f, b, ',');
    std::getline(f, c, ',');
    const double ts = std::stod(a);
    EXPECT_GT(ts, t);
    t = ts;
    sum += std::stoll(b);
    position = std::stoll(c);
    EXPECT_EQ(position, sum);
  }
  EXPECT_EQ(rows, u["steps_issued"].get<long long>());
  EXPECT_EQ(sum, u["final_position_steps"].get<long long>());
  EXPECT_LT(t, 1.0);

  std::istringstream series(read_file(csv));
  std::getline(series, line);
  EXPECT_EQ(line, "t_s,x_m_m,x_w_m,x_t_m,force_N");
  int n = 0;
  while (std::getline(series, line)) {
    std::vector<double> v;
    std::istringstream f(line);
    std::string x;
    while (std::getline(f, x, ',')) v.push_back(std::stod(x));
    ASSERT_EQ(v.size(), 5u);
    EXPECT_NEAR(v[3] / 0.00067, std::round(v[3] / 0.00067), 1e-6) << line;
    ++n;
  }
  EXPECT_EQ(n, 2001);  // t = 0 and 400 per revolution over five revolutions
  // the same input, the same bytes
  const std::string steps2 = sc.path("steps2.csv");
  EXPECT_EQ(run_cli("chatter " + kExamples + "dunckley-suppressor.toml --simulate 1311 --suppress --duration \"1 s\" "
                    "--steps-out " + steps2).code, 0);
  EXPECT_EQ(read_file(steps2), read_file(steps));
}

TEST(CliChatter, SuppressorRefusals) {
  Scratch sc;
  const std::string out = sc.path("steps.csv");
  expect_refused(run_cli("chatter " + kExamples + "dunckley-suppressor.toml --suppress --steps-out " + out), sc, out,
                 "--suppress");
  expect_refused(run_cli("chatter " + kExamples + "dunckley-suppressor.toml --simulate 1311 --steps-out " + out), sc,
                 out, "--steps-out");
  expect_refused(run_cli("chatter " + kExamples + "dunckley-case1.toml --simulate 1311 --suppress --steps-out " + out),
                 sc, out, "has no [suppressor] table");
}

TEST(CliIdentify, RecoversTheStructure) {
  Scratch sc;
  const auto j = cli_json("identify " + sc.write("r.csv", response_csv(true)) + " --json");
  for (const char* k : {"least_squares", "recursive_least_squares"}) {
    SCOPED_TRACE(k);
    EXPECT_NEAR(j[k]["omega_n_rad_s"].get<double>(), 300.0, 0.003);
    EXPECT_NEAR(j[k]["zeta"].get<double>(), 0.03, 1e-5);
    EXPECT_NEAR(j[k]["gain_m_per_N"].get<double>(), 1e-6, 1e-9);
  }
  const auto f = cli_json("identify " + sc.write("free.csv", response_csv(false)) + " --json");
  EXPECT_TRUE(f["least_squares"].is_null());
  EXPECT_NEAR(f["log_decrement"]["zeta"].get<double>(), 0.03, 0.0006);
  EXPECT_NEAR(f["log_decrement"]["omega_n_rad_s"].get<double>(), 300.0, 1.5);
}

TEST(CliIdentify, BadInputIsOneLine) {
  Scratch sc;
  expect_one_line_error(run_cli("identify " + sc.write("h.csv", "time,x\n0,1\n")), "h.csv:1");
  expect_one_line_error(run_cli("identify " + sc.write("flat.csv", "t_s,displacement_m\n0,1\n1,1\n2,1\n3,1\n4,1\n5,1\n6,1\n7,1\n")),
                        "flat.csv");
  expect_one_line_error(run_cli("identify " + sc.write("r.csv", response_csv(true)) + " --forgetting 1.5"),
                        "--forgetting");
  // a small factor makes the recursive estimate overflow on this record: refused by name, not printed as NaN
  const auto diverged = run_cli("identify " + sc.write("r.csv", response_csv(true)) + " --forgetting 0.1");
  expect_one_line_error(diverged, "forgetting factor");
  EXPECT_EQ(diverged.err.find("nan"), std::string::npos) << diverged.err;
  // a free response has no force: the factor would weigh nothing
  expect_one_line_error(run_cli("identify " + sc.write("free.csv", response_csv(false)) + " --forgetting 0.9"),
                        "--forgetting: weights the recursive least squares");
}

}  // namespace tu_cli_test_cli_chatter
}  // namespace polarcam::test
