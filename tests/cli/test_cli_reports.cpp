// The operator's report of a job with dynamics shows both schedules (the time-optimal one and the best constant
// speed at the job's safety factor) and, with [process] chatter, the stability lobes; `capacity` of a time-optimal
// job (refused without --speed, the constant-speed capacity with it) (docs/time-optimal.md, docs/chatter.md); with
// a milling load, the cut along the path (docs/process.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_reports {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::string example(const std::string& name) {
  return read_file(std::string(POLARCAM_SOURCE_DIR) + "/examples/" + name);
}

// The example job copied into the scratch directory beside its machine file (../machines/ as in examples/ch6).
std::string copy_ch6(const Scratch& sc, const std::string& name, const std::string& text) {
  fs::create_directories(sc.dir / "ch6");
  return sc.write("ch6/" + name + ".toml", text);
}

// The inertial witch of Ch. 6 as a time-optimal job under 30 cm/s.
std::string topt_witch() {
  return replace(example("ch6/witch_inertial.toml"), "speed = \"1.524 cm/s\"",
                 "speed = \"30 cm/s\"\nspeed_profile = \"time-optimal\"");
}

const char* kReportOptions = " --map-size 5 --max-evaluations 30 --threads 2 --quiet";

// The number before " s</td>" in the table row whose first cell is `first` (NaN when there is none).
double row_seconds(const std::string& html, const std::string& first) {
  const std::string key = "<tr><td>" + first + "</td><td>";
  const size_t p = html.find(key);
  if (p == std::string::npos) return std::nan("");
  const size_t b = p + key.size(), e = html.find(" s</td>", b);
  if (e == std::string::npos) return std::nan("");
  return std::stod(html.substr(b, e - b));
}

// The HTML between the heading of section `id` and the next section's heading.
std::string section(const std::string& html, const std::string& id) {
  const size_t p = html.find("id=\"" + id + "\"");
  if (p == std::string::npos) return "";
  const size_t e = html.find("<h2", p);
  return html.substr(p, e == std::string::npos ? std::string::npos : e - p);
}

}  // namespace

TEST(CliReportSchedules, TimeOptimalJobIsGoWithBothSchedulesTimes) {
  Scratch sc;
  const std::string job = copy_ch6(sc, "topt", topt_witch()), out = sc.path("topt.html");
  const CliResult r = run_cli("report " + job + " -o " + out + kReportOptions);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_EQ(r.out.rfind("GO:", 0), 0u) << r.out;
  const std::string html = read_file(out);
  const std::string speed = section(html, "speed");
  ASSERT_FALSE(speed.empty());
  EXPECT_NE(html.find("time-optimal schedule, at most 30 cm/s"), std::string::npos);  // the job table
  // both times, as `optimize-speed` plans them (printed to 5 digits)
  const json plan = cli_json("optimize-speed " + job + " --json");
  const double t = row_seconds(speed, "time-optimal schedule");
  const double tc = row_seconds(speed, "best constant speed at safety factor 1.2");
  EXPECT_NEAR(t, plan["time_optimal_s"].get<double>(), 1e-4 * t);
  EXPECT_NEAR(tc, plan["constant_time_s"].get<double>(), 1e-4 * tc);
  // the constant time is the path's length at the constant speed; the schedule beats it
  EXPECT_NEAR(tc, plan["path_length_m"].get<double>() / plan["constant_speed_mps"].get<double>(), 1e-4 * tc);
  EXPECT_LT(t, tc);
  EXPECT_NE(speed.find("This job runs the time-optimal schedule"), std::string::npos);
  EXPECT_NE(speed.find("saves"), std::string::npos);
  EXPECT_NE(speed.find("<img"), std::string::npos);  // the figure of both schedules
  // the verdict is that of the schedule: `analyze` of the job
  EXPECT_EQ(cli_json("analyze " + job + " --json")["verdict"], "GO");
  // the capacity and the placements at the best constant speed, said so
  EXPECT_NE(section(html, "capacity").find("run at the best constant speed"), std::string::npos);
  for (const char* id : {"verdict", "job", "workarea", "tape", "accuracy", "torque", "capacity", "pole", "tradeoff"})
    EXPECT_NE(html.find(std::string("id=\"") + id + "\""), std::string::npos) << id;
}

TEST(CliReportSchedules, ConstantSpeedJobNamesTheSaving) {
  Scratch sc;
  const std::string job = copy_ch6(sc, "witch_grinding", example("ch6/witch_grinding.toml"));
  const std::string out = sc.path("wg.html");
  const CliResult r = run_cli("report " + job + " -o " + out + kReportOptions);
  // the verdict stays that of the job's own speed
  EXPECT_EQ(r.code, run_cli("analyze " + job).code) << r.out << r.err;
  const std::string speed = section(read_file(out), "speed");
  ASSERT_FALSE(speed.empty());
  EXPECT_NE(speed.find("This job runs at one constant speed"), std::string::npos);
  const json plan = cli_json("optimize-speed " + job + " --json");
  const double t = row_seconds(speed, "time-optimal schedule");
  const double tc = row_seconds(speed, "best constant speed at safety factor 1.2");
  EXPECT_NEAR(t, plan["time_optimal_s"].get<double>(), 1e-4 * t);
  EXPECT_NEAR(tc, plan["constant_time_s"].get<double>(), 1e-4 * tc);
  // the saving named, in seconds: the difference of the two times
  const size_t p = speed.find("The time-optimal schedule saves ");
  ASSERT_NE(p, std::string::npos) << speed;
  const double saved = std::stod(speed.substr(p + 32));
  EXPECT_NEAR(saved, tc - t, 2e-3 * (tc - t));
  // this job's own time: its path at 1.016 cm/s
  const double tj = row_seconds(speed, "this job");
  EXPECT_NEAR(tj, plan["path_length_m"].get<double>() / 0.01016, 1e-3 * tj);
  EXPECT_NE(speed.find("against this job's speed"), std::string::npos);
}

TEST(CliCapacity, TimeOptimalJobNeedsASpeed) {
  Scratch sc;
  const std::string job = copy_ch6(sc, "topt", topt_witch());
  expect_one_line_error(run_cli("capacity " + job), "--speed");
  // with --speed: the capacity of the job at that constant speed
  const std::string constant =
      copy_ch6(sc, "constant", replace(example("ch6/witch_inertial.toml"), "speed = \"1.524 cm/s\"", "speed = \"2 cm/s\""));
  const json a = cli_json("capacity " + job + " --speed \"2 cm/s\" --json");
  const json b = cli_json("capacity " + constant + " --json");
  // the same numbers but for the job's name
  for (const char* key : {"speed_mps", "max_speed_mps", "max_usable_speed_mps", "load_at_job", "load_at_speed_mps",
                          "worst_torque_ratio_at_max_load"})
    EXPECT_EQ(a[key], b[key]) << key;
  EXPECT_DOUBLE_EQ(a["speed_mps"].get<double>(), 0.02);
}

TEST(CliReportChatter, JobWithAChatterStructureHasItsLobes) {
  Scratch sc;
  fs::create_directories(sc.dir / "process");
  sc.write("process/dunckley-case2.toml", example("process/dunckley-case2.toml"));
  const std::string job = sc.write("wgc.toml", example("witch_grinding_chatter.toml")), out = sc.path("wgc.html");
  const CliResult r = run_cli("report " + job + " -o " + out + kReportOptions);
  ASSERT_TRUE(r.code == 0 || r.code == 1) << r.err;
  const std::string chatter = section(read_file(out), "chatter");
  ASSERT_FALSE(chatter.empty());
  EXPECT_NE(chatter.find("<img alt=\"stability lobes"), std::string::npos);
  // the critical gain as `polarcam chatter` finds it, to the 5 digits printed
  const json c = cli_json("chatter " + sc.path("process/dunckley-case2.toml") + " --json");
  const double k = c["critical_gain"];
  const std::string key = "<td>critical cutting gain (Nyquist)</td><td>";
  const size_t p = chatter.find(key);
  ASSERT_NE(p, std::string::npos);
  EXPECT_NEAR(std::stod(chatter.substr(p + key.size())), k, 1e-4 * k);
  // a job without the key has no such section
  Scratch sc2;
  const std::string plain = copy_ch6(sc2, "wg", example("ch6/witch_grinding.toml"));
  run_cli("report " + plain + " -o " + sc2.path("wg.html") + kReportOptions);
  EXPECT_EQ(read_file(sc2.path("wg.html")).find("id=\"chatter\""), std::string::npos);
}

TEST(CliReportChatter, MissingStructureFileIsOneLineNamingTheKey) {
  Scratch sc;
  const std::string job = sc.write("wgc.toml", example("witch_grinding_chatter.toml"));
  const std::string out = sc.path("wgc.html");
  const CliResult r = run_cli("report " + job + " -o " + out);
  expect_one_line_error(r, "process.chatter");
  EXPECT_NE(r.err.find("dunckley-case2.toml"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  // an unknown key of [process] too
  const std::string bad = sc.write("bad.toml", replace(example("witch_grinding_chatter.toml"), "chatter =", "chattr ="));
  expect_one_line_error(run_cli("analyze " + bad), "process.chattr");
}

// The report of a job with a milling load has its "Cutting" section with the figures of `polarcam process` (about
// 15 s of CPU in a Release build: under the sanitizers only with POLARCAM_LONG_TESTS=1).
TEST(CliReportCutting, MillingJobHasItsCuttingSection) {
#ifdef POLARCAM_SANITIZED
  const char* e = std::getenv("POLARCAM_LONG_TESTS");
  if (!e || std::string(e) != "1") GTEST_SKIP() << "checked in the normal build";
#endif
  Scratch sc;
  fs::create_directories(sc.dir / "process");
  fs::create_directories(sc.dir / "machines");
  for (const char* f : {"process/contour_milling.toml", "process/fussell_table1.toml", "machines/fahim1983.toml"})
    sc.write(f, example(f));
  const std::string job = sc.path("process/contour_milling.toml"), out = sc.path("cm.html");
  const CliResult r = run_cli("report " + job + " -o " + out + " --map-size 4 --max-evaluations 20 --threads 2 --quiet");
  ASSERT_TRUE(r.code == 0 || r.code == 1) << r.err;
  const std::string cutting = section(read_file(out), "cutting");
  ASSERT_FALSE(cutting.empty());
  const json p = cli_json("process " + job + " --json");
  char text[64];
  std::snprintf(text, sizeof text, "the path takes %.4g s", p["duration_s"].get<double>());
  EXPECT_NE(cutting.find(text), std::string::npos) << cutting;
  EXPECT_NE(cutting.find("<td>the nominal force</td>"), std::string::npos) << cutting;
  EXPECT_NE(cutting.find("<img"), std::string::npos);
}

}  // namespace tu_cli_test_cli_reports
