// End-to-end tests of `polarcam compare` and of `polarcam error` on Cartesian tapes: the JSON members the issue
// names, the HTML report (self-contained, deterministic), and bad input (one line, exit code 2, no report left).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_compare {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;

namespace {

// A small job: a circle of radius 8 mm about (3 mm, -2 mm), the polar pole 30 mm away, a 0.05 mm grid.
const std::string kJob = cli_job("small_circle.toml");

}  // namespace

TEST(CompareCli, JsonHasBothMachinesAndTheNamedKeys) {
  Scratch sc;
  const std::string job = sc.write("job.toml", kJob);
  for (const char* method : {"dda", "exact"}) {
    const json j = cli_json("compare " + job + " --json --method " + method);
    for (const char* side : {"polar", "cartesian"}) {
      SCOPED_TRACE(std::string(method) + " " + side);
      ASSERT_TRUE(j.contains(side));
      const json& s = j[side];
      for (const char* k : {"steps_total", "duration_s", "speed_min_mps", "speed_max_mps", "speed_rms_dev_mps",
                            "area_error_mm2", "deviation_max_mm", "max_step_rate_hz", "tape_bytes", "resolution_worst_mm",
                            "speed_scaling", "size_scaling"})
        EXPECT_TRUE(s.contains(k)) << k;
      EXPECT_GT(s["steps_total"].get<double>(), 0);
      EXPECT_GT(s["area_error_mm2"].get<double>(), 0);
      EXPECT_GT(s["deviation_max_mm"].get<double>(), 0);
      EXPECT_LT(s["deviation_max_mm"].get<double>(), 0.2);  // a fraction of a mm on a 0.05 mm grid
      EXPECT_NEAR(s["duration_s"].get<double>(), 2 * 3.14159265 * 8 / 10, 0.02);
    }
    EXPECT_TRUE(j["polar"].contains("steps_radial"));
    EXPECT_TRUE(j["cartesian"].contains("steps_x"));
    EXPECT_EQ(j["cartesian"]["method"], method);
    EXPECT_EQ(j["cartesian"]["speed_scaling"]["without_reprocessing"], std::string(method) == "exact");
    ASSERT_EQ(j["verdicts"].size(), 9u);
    for (const json& v : j["verdicts"]) {
      const std::string w = v["winner"];
      EXPECT_TRUE(w == "polar" || w == "cartesian" || w == "tie") << w;
      EXPECT_FALSE(v["why"].get<std::string>().empty());
    }
  }
}

// The report: one file, images inline, no scripts or remote resources; the same bytes on a second run.
TEST(CompareCli, ReportIsSelfContainedAndDeterministic) {
  Scratch sc;
  const std::string job = sc.write("job.toml", kJob);
  const std::string a = sc.path("a.html"), b = sc.path("b.html");
  CliResult r1 = run_cli("compare " + job + " --report " + a);
  ASSERT_EQ(r1.code, 0) << r1.err;
  CliResult r2 = run_cli("compare " + job + " --report " + b);
  ASSERT_EQ(r2.code, 0) << r2.err;
  EXPECT_EQ(r1.out, r2.out);
  const std::string h = read_file(a);
  EXPECT_EQ(h, read_file(b));
  EXPECT_NE(h.find("<!DOCTYPE html>"), std::string::npos);
  EXPECT_NE(h.find("Which machine is better for this job"), std::string::npos);
  // no type names or number agreement slips in the text
  EXPECT_EQ(h.find("AttributeVerdict"), std::string::npos);
  EXPECT_EQ(h.find(" 1 are "), std::string::npos);
  EXPECT_NE(h.find("Tangential speed along the path"), std::string::npos);
  size_t images = 0;
  for (size_t p = h.find("data:image/png;base64,"); p != std::string::npos; p = h.find("data:image/png;base64,", p + 1))
    ++images;
  EXPECT_EQ(images, 3u);
  EXPECT_EQ(h.find("<script"), std::string::npos);
  EXPECT_EQ(h.find("http://"), std::string::npos);
  EXPECT_EQ(h.find("https://"), std::string::npos);
  EXPECT_NE(r1.out.find("which machine wins"), std::string::npos);
}

TEST(CompareCli, BadInputIsOneLineAndNoReport) {
  Scratch sc;
  const std::string job = sc.write("job.toml", kJob), report = sc.path("r.html");
  expect_one_line_error(run_cli("compare " + job + " --method exact --rate 5000 --report " + report), "--rate");
  expect_one_line_error(run_cli("compare " + job + " --size-scale 0 --report " + report), "--size-scale");
  expect_one_line_error(run_cli("compare " + job + " --speed-scale x2 --report " + report), "--speed-scale");
  expect_one_line_error(run_cli("compare " + job + " --rate 10mm --report " + report), "frequency");
  expect_one_line_error(run_cli("compare " + sc.path("missing.toml") + " --report " + report), "missing.toml");
  std::string ramp = kJob;
  ramp += "accel = \"100 mm/s^2\"\n";
  const std::string rj = sc.write("ramp.toml", ramp);
  expect_one_line_error(run_cli("compare " + rj + " --report " + report), "ramp.toml");
  EXPECT_FALSE(std::filesystem::exists(report));
  // the report is HTML: another name is refused before any work, and nothing is written under it
  expect_one_line_error(run_cli("compare " + job + " --report " + sc.path("r.svg")), "the report is written as .html or .htm");
  EXPECT_FALSE(std::filesystem::exists(sc.path("r.svg")));
  EXPECT_EQ(run_cli("compare " + job + " --report " + sc.path("R.HTML")).code, 0);
  // a report that cannot be written
  // an output that cannot be created is an I/O error (exit status 3), still one line
  expect_one_line_error(run_cli("compare " + job + " --report " + sc.path("no/such/dir/r.html")), "r.html", 3);
}

// `polarcam error` on a Cartesian tape: area error and deviation, refused against another job or with F1 options.
TEST(CompareCli, ErrorReadsCartesianTapes) {
  Scratch sc;
  const std::string job = sc.write("job.toml", kJob), tape = sc.path("c.tape");
  ASSERT_EQ(run_cli("dda " + job + " -o " + tape).code, 0);
  const json j = cli_json("error " + tape + " --job " + job + " --json");
  EXPECT_EQ(j["axes"], "cartesian");
  EXPECT_EQ(j["rule"], "dda");
  EXPECT_GT(j["area_error_mm2"].get<double>(), 0.0);
  EXPECT_GT(j["deviation_max_mm"].get<double>(), 0.0);
  EXPECT_FALSE(j.contains("F1"));
  // the same numbers as compare reports for the same tape
  const json cj = cli_json("compare " + job + " --json");
  EXPECT_DOUBLE_EQ(cj["cartesian"]["area_error_mm2"].get<double>(), j["area_error_mm2"].get<double>());
  EXPECT_DOUBLE_EQ(cj["cartesian"]["deviation_max_mm"].get<double>(), j["deviation_max_mm"].get<double>());

  expect_one_line_error(run_cli("error " + tape + " --job " + job + " --segments 10"), "--segments");
  std::string moved = kJob;
  moved.replace(moved.find("center_x = \"3 mm\""), 17, "center_x = \"9 mm\"");
  const std::string other = sc.write("other.toml", moved);
  expect_one_line_error(run_cli("error " + tape + " --job " + other), "does not follow this path");
}

}  // namespace tu_cli_test_cli_compare
