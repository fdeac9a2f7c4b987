// End-to-end tests of `polarcam error` and `polarcam optimize`: outputs, the written job, maps, determinism and
// bad input (one line naming the file and key, exit code 2, no output file).
#include <gtest/gtest.h>

#include <vector>

#include <cmath>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/cli_runner.hpp"
#include "digitizer/tape.hpp"

namespace tu_cli_test_optimize_cli {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;

const std::string kJob = cli_job("own_machine_circle.toml");

TEST(ErrorCli, MetricsOfTapesOfBothRules) {
  Scratch sc;
  const std::string job = sc.write("c.toml", kJob);
  double areas[2];
  int k = 0;
  for (const char* rule : {"nearest", "thesis"}) {
    const std::string j = sc.write(std::string("c_") + rule + ".toml",
                                   replace(kJob, "speed = \"1 cm/s\"", std::string("speed = \"1 cm/s\"\nrule = \"") + rule + "\""));
    const std::string tape = sc.path(std::string(rule) + ".tape");
    ASSERT_EQ(run_cli("digitize " + j + " -o " + tape).code, 0);
    // the tape is measured against the path of either job file: the rule does not enter the metric
    json m = cli_json("error " + tape + " --job " + job + " --json");
    for (const char* key : {"area_error_mm2", "deviation_max_mm", "F_sum", "F_dif", "F1", "F1_chords", "deviation_eq41_mm"})
      EXPECT_TRUE(m[key].is_number()) << key;
    EXPECT_EQ(m["rule"], rule);
    EXPECT_GT(m["area_error_mm2"].get<double>(), 0.0);
    EXPECT_NEAR(m["F1"].get<double>(), m["F_dif"].get<double>() / m["F_sum"].get<double>(), 1e-12);
    areas[k++] = m["area_error_mm2"].get<double>();
    // one thread or the deviation beside the area meter: the same bytes
    EXPECT_EQ(run_cli("error " + tape + " --job " + job + " --json --threads 1").out,
              run_cli("error " + tape + " --job " + job + " --json --threads 2").out);
    CliResult t = run_cli("error " + tape + " --job " + job);
    EXPECT_EQ(t.code, 0);
    EXPECT_NE(t.out.find("area error"), std::string::npos);
  }
  // truncation (thesis) leaves the staircase on one side of the contour: more area than rounding
  EXPECT_GT(areas[1], areas[0]);
}

TEST(ErrorCli, BadInput) {
  Scratch sc;
  const std::string job = sc.write("c.toml", kJob), tape = sc.path("c.tape");
  ASSERT_EQ(run_cli("digitize " + job + " -o " + tape).code, 0);
  // a tape made at another placement does not follow the job's path
  const std::string other = sc.write("other.toml", replace(kJob, "beta = \"4.9 rad\"", "beta = \"4.5 rad\""));
  expect_one_line_error(run_cli("error " + tape + " --job " + other), "does not follow");
  // a damaged tape
  const std::string bad = sc.path("bad.tape");
  std::filesystem::copy_file(tape, bad);
  {
    std::fstream f(bad, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(std::filesystem::file_size(bad) - 3));
    f.put('\x55');
  }
  expect_one_line_error(run_cli("error " + bad + " --job " + job), "bad.tape");
  // a Cartesian tape
  const std::string cart = sc.path("cart.tape");
  {
    polarcam::TapeHeader h;
    h.axes = polarcam::TapeAxes::cartesian;
    h.rule = polarcam::TapeRule::dda;
    h.res[0] = h.res[1] = 1e-4;
    polarcam::TapeWriter w(cart, h);
    w.write({10, 0, 1});
    polarcam::TapeHeader done = h;
    done.end[0] = 1;
    w.finish(done);
  }
  expect_one_line_error(run_cli("error " + cart + " --job " + job), "Cartesian");
}

TEST(OptimizeCli, JsonWriteJobAndMaps) {
  Scratch sc;
  const std::string job = sc.write("c.toml", kJob);
  std::filesystem::create_directories(sc.dir / "out");
  const std::string written = sc.path("out/best.toml"), csv = sc.path("map.csv"), png = sc.path("map.png");
  json o = cli_json("optimize " + job + " --json --write-job " + written + " --map " + csv + " --map-image " + png +
                        " --map-size 9");
  for (const char* key : {"C_mm", "beta_rad", "area_error_mm2", "objective", "evaluations", "F1"})
    EXPECT_TRUE(o[key].is_number()) << key;
  EXPECT_EQ(o["objective_name"], "area");
  EXPECT_EQ(o["objective"].get<double>(), o["area_error_mm2"].get<double>());
  EXPECT_LE(o["area_error_mm2"].get<double>(), o["start"]["area_error_mm2"].get<double>());
  EXPECT_LE(o["evaluations"].get<int>(), 80);
  // the two descriptions of the placement: O - O1 and O1 - O
  EXPECT_NEAR(std::remainder(o["contour_pole_beta_rad"].get<double>() - o["beta_rad"].get<double>() - std::numbers::pi, 2 * std::numbers::pi), 0.0,
              1e-12);
  EXPECT_DOUBLE_EQ(o["contour_pole_x_mm"].get<double>(), -o["pole_x_mm"].get<double>());
  EXPECT_NEAR(std::hypot(o["pole_x_mm"].get<double>(), o["pole_y_mm"].get<double>()), o["C_mm"].get<double>(), 1e-9);

  // the written job (in another directory: its machine file is found) reproduces the reported area exactly
  ASSERT_TRUE(std::filesystem::exists(written));
  const std::string tape = sc.path("best.tape");
  CliResult d = run_cli("digitize " + written + " -o " + tape);
  ASSERT_EQ(d.code, 0) << d.err;
  CliResult e = run_cli("error " + tape + " --job " + written + " --json");
  ASSERT_EQ(e.code, 0) << e.err;
  EXPECT_NEAR(json::parse(e.out)["area_error_mm2"].get<double>(), o["area_error_mm2"].get<double>(),
              1e-12 * o["area_error_mm2"].get<double>());

  // the map: 9 x 9 rows, PNG written; the same bytes on one thread
  std::ifstream in(csv);
  std::string line;
  int rows = 0, feasible = 0;
  while (std::getline(in, line)) {
    ++rows;
    if (rows > 1 && line.find(",1,") != std::string::npos) ++feasible;
  }
  EXPECT_EQ(rows, 82);
  EXPECT_GT(feasible, 0);
  EXPECT_EQ(read_file(png).substr(1, 3), "PNG");
  const std::string csv1 = sc.path("map1.csv");
  CliResult r1 = run_cli("optimize " + job + " --json --threads 1 --map " + csv1 + " --map-size 9");
  ASSERT_EQ(r1.code, 0) << r1.err;
  EXPECT_EQ(read_file(csv), read_file(csv1));
  json o1 = json::parse(r1.out);
  EXPECT_EQ(o1["C_mm"], o["C_mm"]);
  EXPECT_EQ(o1["beta_rad"], o["beta_rad"]);
}

TEST(OptimizeCli, F1HoldsAndBadInput) {
  Scratch sc;
  const std::string job = sc.write("c.toml", kJob);
  json o = cli_json("optimize " + job + " --objective f1 --hold C --json");
  EXPECT_EQ(o["method"], "hooke-jeeves");
  EXPECT_DOUBLE_EQ(o["C_mm"].get<double>(), 50.0);
  EXPECT_EQ(o["objective"].get<double>(), o["F1"].get<double>());

  expect_one_line_error(run_cli("optimize " + sc.write("k.toml", replace(kJob, "threads = 2", "threads = 2\nbogus = 1"))),
                        "optimize.bogus");
  expect_one_line_error(run_cli("optimize " + sc.write("o.toml", replace(kJob, "max_evaluations = 80", "objective = \"speed\""))),
                        "optimize.objective");
  expect_one_line_error(run_cli("optimize " + sc.write("z.toml", replace(kJob, "C = \"5 cm\"", "C = \"0 cm\"")) + " --hold C"),
                        "nothing to optimise");
  // a bad image name is refused before anything is written
  const std::string csv = sc.path("never.csv");
  expect_one_line_error(run_cli("optimize " + job + " --map " + csv + " --map-image " + sc.path("m.jpg")), ".png or .svg");
  EXPECT_FALSE(std::filesystem::exists(csv));
  // options that would be ignored are refused, naming themselves: each applies to another objective or output
  const std::string ch6 = std::string(POLARCAM_SOURCE_DIR) + "/examples/ch6/circle_inertial.toml";
  for (const auto& [args, mention] : std::vector<std::pair<std::string, std::string>>{
           {job + " --map-size 5", "--map-size: sizes the map"},
           {job + " --levels 3", "--levels: applies to --objective pareto"},
           {job + " --survey 5", "--survey: applies to --objective pareto"},
           {job + " --objective area --segments 7", "--segments: applies to --objective f1"},
           {ch6 + " --speed \"30 cm/s\"", "--speed: the area error and F1 do not depend on it"},
           {ch6 + " --objective f1 --safety-factor 5", "--safety-factor: the area error and F1 do not depend on it"},
           {ch6 + " --objective pareto --method hooke-jeeves", "--method"},
           {ch6 + " --objective pareto --torque-limit", "--torque-limit"},
           {ch6 + " --objective pareto --map-size 5", "--map-size"}}) {
    SCOPED_TRACE(args);
    expect_one_line_error(run_cli("optimize " + args), mention);
  }
  // a pole where the path touches r_max exactly (the balanced circle's): the job at that pole is digitized, not
  // refused for a radius beyond r_max by a rounding of the track built another way
  const CliResult edge = run_cli("optimize " + std::string(POLARCAM_SOURCE_DIR) + "/examples/circle.toml --objective balanced --json --quiet");
  ASSERT_EQ(edge.code, 0) << edge.err;
  EXPECT_NEAR(json::parse(edge.out)["C_mm"].get<double>(), 330.2 - 50.8, 1e-6);  // r_max less the circle's radius
  // where they apply they are taken
  EXPECT_EQ(run_cli("optimize " + ch6 + " --speed \"1 cm/s\" --torque-limit --safety-factor 1.5 --max-evaluations 40 --quiet").code, 0);
  // a job with [optimize] still digitizes as before
  EXPECT_EQ(run_cli("digitize " + job).code, 0);
}

}  // namespace tu_cli_test_optimize_cli
