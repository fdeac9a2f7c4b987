// End-to-end tests of the optimum-loading commands (docs/optimum-loading.md): `optimize --objective balanced|pareto
// --json`, `capacity --json` fed back into `analyze`, and the operator's report (`report`): its sections for every
// example job, self-contained, and rendered in headless Chromium to a screenshot that is not blank.
#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_optimum {  // the test files of a program compile together (unity build)

using namespace polarcam::test;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::string example_text(const std::string& name) {
  return read_file(std::string(POLARCAM_SOURCE_DIR) + "/examples/ch6/" + name + ".toml");
}

// The example job copied into the scratch directory (its machine file at ../machines/ as in examples/).
std::string copy_example(const Scratch& sc, const std::string& name, const std::string& text) {
  fs::create_directories(sc.dir / "ch6");
  return sc.write("ch6/" + name + ".toml", text);
}

double worst_ratio(const json& a) {
  return std::max(a["radial"]["max_torque_ratio"].get<double>(), a["angular"]["max_torque_ratio"].get<double>());
}

std::string quantity(double v, const char* unit) {
  char b[64];
  std::snprintf(b, sizeof b, "\"%.12g %s\"", v, unit);
  return b;
}

}  // namespace

TEST(CliOptimum, BalancedPlacementIsWhatAnalyzeSaysThere) {
  Scratch sc;
  const std::string job = copy_example(sc, "witch_grinding", example_text("witch_grinding"));
  const json j = cli_json("optimize " + job + " --objective balanced --json --max-evaluations 120 --threads 2");
  for (const char* k : {"C_mm", "beta_rad", "objective", "max_torque_ratio_radial", "max_torque_ratio_angular"})
    ASSERT_TRUE(j[k].is_number()) << k;
  const double Rr = j["max_torque_ratio_radial"], Rt = j["max_torque_ratio_angular"];
  EXPECT_EQ(j["objective_name"], "balanced");
  // the objective T_T / |1 - |T_R - T_theta|| is at least the largest ratio sum, and it improved on the job's pole
  EXPECT_GE(j["objective"].get<double>(), j["max_ratio_sum"].get<double>() * (1 - 1e-12));
  EXPECT_LE(j["objective"].get<double>(), j["start"]["balanced_objective"].get<double>());
  // `analyze` at the reported placement gives the same ratios
  const std::string placed = copy_example(
      sc, "placed",
      replace(replace(example_text("witch_grinding"), "C = \"25.4 cm\"", "C = " + quantity(j["C_mm"], "mm")),
              "beta = \"pi/2 rad\"", "beta = " + quantity(j["beta_rad"], "rad")));
  CliResult a = run_cli("analyze " + placed + " --json");
  ASSERT_TRUE(a.code == 0 || a.code == 1) << a.err;
  const json ja = json::parse(a.out);
  EXPECT_NEAR(ja["radial"]["max_torque_ratio"].get<double>(), Rr, 1e-6 * Rr);
  EXPECT_NEAR(ja["angular"]["max_torque_ratio"].get<double>(), Rt, 1e-6 * Rt);
  // same input, same bytes (the JSON carries no wall time)
  CliResult again = run_cli("optimize " + job + " --objective balanced --json --max-evaluations 120 --threads 1");
  EXPECT_FALSE(j.contains("wall_s"));
  EXPECT_EQ(json::parse(again.out).dump(), j.dump());  // with 2 threads and with 1
}

TEST(CliOptimum, TorqueLimitedAreaOptimumPassesAnalyze) {
  // `--objective area --torque-limit`: the least area error among the poles the drives can carry. The witch ground
  // at its Ch. 5 pole is NO-GO (radial ratio 0.906 > 1/1.2); the pole found must be GO in `analyze`.
  Scratch sc;
  const std::string text = example_text("witch_grinding");
  const std::string job = copy_example(sc, "witch_grinding", text);
  const json j = cli_json("optimize " + job + " --objective area --torque-limit --json --max-evaluations 40 --threads 2");
  const double limit = j["torque_limit"];
  EXPECT_NEAR(limit, 1.0 / 1.2, 1e-12);
  EXPECT_LE(j["worst_torque_ratio"].get<double>(), limit);
  EXPECT_EQ(j["start"]["verdict"], "NO-GO");
  const std::string placed = copy_example(
      sc, "placed",
      replace(replace(text, "C = \"25.4 cm\"", "C = " + quantity(j["C_mm"], "mm")), "beta = \"pi/2 rad\"",
              "beta = " + quantity(j["beta_rad"], "rad")));
  CliResult a = run_cli("analyze " + placed + " --json");
  EXPECT_EQ(a.code, 0) << a.out;
  EXPECT_LE(worst_ratio(json::parse(a.out)), limit);
  // twice the depth of cut: no pole passes; one line saying so, exit 2
  const std::string heavy = copy_example(sc, "heavy", replace(text, "depth = \"0.001 in\"", "depth = \"0.002 in\""));
  CliResult h = run_cli("optimize " + heavy + " --objective area --torque-limit --max-evaluations 40 --threads 2");
  EXPECT_EQ(h.code, 2);
  EXPECT_NE(h.err.find("no pole position"), std::string::npos) << h.err;
  EXPECT_EQ(std::count(h.err.begin(), h.err.end(), '\n'), 1) << h.err;
}

TEST(CliOptimum, ParetoFrontIsNonDominated) {
  Scratch sc;
  const std::string job = copy_example(sc, "circle_grinding", example_text("circle_grinding"));
  const json j = cli_json("optimize " + job +
                        " --objective pareto --json --max-evaluations 20 --levels 1 --survey 4 --threads 2");
  ASSERT_TRUE(j["points"].is_array());
  ASSERT_GE(j["points"].size(), 2u);
  double prev_ratio = -1, prev_area = 1e300;
  for (const json& p : j["points"]) {
    for (const char* k : {"C_mm", "beta_rad", "area_error_mm2", "max_torque_ratio_radial", "max_torque_ratio_angular"})
      ASSERT_TRUE(p[k].is_number()) << k;
    const double w = std::max(p["max_torque_ratio_radial"].get<double>(), p["max_torque_ratio_angular"].get<double>());
    // by worst ratio increasing, area error strictly decreasing: no point dominates another
    EXPECT_GE(w, prev_ratio);
    EXPECT_LT(p["area_error_mm2"].get<double>(), prev_area);
    prev_ratio = w, prev_area = p["area_error_mm2"];
  }
}

TEST(CliOptimum, CapacitySpeedAndLoadFedBackIntoAnalyzeGiveTheLimit) {
  Scratch sc;
  struct Case {
    const char* name;
    const char* key;       // the load's key in the job file
    const char* old_line;  // its line, replaced by the largest load
    const char* unit;
  };
  for (const Case& c : {Case{"circle_inertial", "max_mass_kg", "mass = \"43.77 kg\"", "kg"},
                        Case{"witch_grinding", "max_depth_mm", "depth = \"0.001 in\"", "mm"}}) {
    SCOPED_TRACE(c.name);
    const std::string text = example_text(c.name);
    const std::string job = copy_example(sc, c.name, text);
    const json j = cli_json("capacity " + job + " --json");
    const double limit = 1.0 / j["safety_factor"].get<double>();
    ASSERT_TRUE(j["max_speed_mps"].is_number());
    ASSERT_TRUE(j[c.key].is_number());
    CliResult a = run_cli("analyze " + job + " --json --speed " + quantity(j["max_speed_mps"], "m/s"));
    ASSERT_TRUE(a.code == 0 || a.code == 1) << a.err;
    EXPECT_NEAR(worst_ratio(json::parse(a.out)), limit, 1e-3);
    const std::string loaded = copy_example(sc, std::string(c.name) + "_max",
                                            replace(text, c.old_line, std::string(c.old_line).substr(0, 
                                                    std::string(c.old_line).find('=') + 2) + quantity(j[c.key], c.unit)));
    CliResult b = run_cli("analyze " + loaded + " --json");
    ASSERT_TRUE(b.code == 0 || b.code == 1) << b.err;
    EXPECT_NEAR(worst_ratio(json::parse(b.out)), limit, 1e-3);
  }
}

TEST(CliOptimum, BadInputIsOneLineAndExitCodeTwo) {
  Scratch sc;
  // a machine without dynamics (no masses, no motors); `report` of such a job is the pattern report
  // (test_cli_pattern_report.cpp)
  const std::string plain = sc.write("circle.toml", cli_job("no_dynamics_circle.toml"));
  for (const std::string& cmd : {"capacity " + plain + " --json", "optimize " + plain + " --objective balanced"}) {
    SCOPED_TRACE(cmd);
    expect_one_line_error(run_cli(cmd), "circle.toml");
  }
  const std::string job = copy_example(sc, "circle_inertial", example_text("circle_inertial"));
  for (const std::string& cmd : {"capacity " + job + " --speed \"-1 cm/s\"", "capacity " + job + " --speed \"1 kg\"",
                                 "report " + job + " -o " + sc.path("r.pdf"),
                                 "optimize " + job + " --objective nonsense"}) {
    CliResult r = run_cli(cmd);
    EXPECT_EQ(r.code, 2) << cmd << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(sc.path("r.pdf")));
}

namespace {

const char* kSections[] = {"verdict", "job", "workarea", "tape", "accuracy", "torque", "capacity", "pole", "tradeoff",
                           "glossary"};

std::string make_report(const Scratch& sc, const std::string& name, int* code = nullptr) {
  const std::string job = copy_example(sc, name, example_text(name));
  const std::string out = sc.path(name + ".html");
  CliResult r = run_cli("report " + job + " -o " + out + " --map-size 5 --max-evaluations 30 --threads 2");
  if (code) *code = r.code;
  // 0 for GO, 1 for NO-GO: the status agrees with the verdict printed
  EXPECT_EQ(r.code, r.out.rfind("GO:", 0) == 0 ? 0 : 1) << r.out << r.err;
  EXPECT_TRUE(r.out.rfind("GO:", 0) == 0 || r.out.rfind("NO-GO:", 0) == 0) << r.out;
  return out;
}

// Fraction of pixels that are not (near) white in a PNG; -1 when it cannot be read.
double ink_fraction(const std::string& file) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, file.c_str())) return -1;
  img.format = PNG_FORMAT_RGB;
  std::vector<png_byte> px(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, px.data(), 0, nullptr)) return -1;
  size_t ink = 0, n = static_cast<size_t>(img.width) * img.height;
  for (size_t i = 0; i < n; ++i)
    if (px[3 * i] < 200 || px[3 * i + 1] < 200 || px[3 * i + 2] < 200) ++ink;
  return n ? static_cast<double>(ink) / static_cast<double>(n) : -1;
}

}  // namespace

// a fixture outside the anonymous namespace: the test class derived from it is in the file's namespace
class ReportOf : public ::testing::TestWithParam<const char*> {};

TEST_P(ReportOf, HasEverySectionAndNeedsNoNetwork) {
  const std::string name = GetParam();
#ifdef POLARCAM_SANITIZED
  // the same code for every job: under the sanitizers, one inertial and one grinding job keep the suite short
  if (name != "circle_inertial" && name != "serpentine_grinding") GTEST_SKIP() << "checked in the normal build";
#endif
  Scratch sc;
  {
    const std::string html = read_file(make_report(sc, name));
    ASSERT_FALSE(html.empty());
    for (const char* id : kSections)
      EXPECT_NE(html.find(std::string("id=\"") + id + "\""), std::string::npos) << "section " << id;
    EXPECT_TRUE(html.find("GO: ") != std::string::npos);  // a verdict line (GO or NO-GO)
    // self-contained: every image inline, nothing fetched
    size_t imgs = 0;
    for (size_t p = html.find("<img"); p != std::string::npos; p = html.find("<img", p + 1)) {
      ++imgs;
      EXPECT_EQ(html.compare(html.find("src=", p), 27, "src=\"data:image/png;base64,"), 0);
    }
    EXPECT_GE(imgs, 5u);
    for (const char* bad : {"http://", "https://", "<script src", "<link", "url("})
      EXPECT_EQ(html.find(bad), std::string::npos) << bad;
    // no NaN or infinity in the text (the images' base64 payloads removed first)
    std::string text;
    for (size_t p = 0; p < html.size();) {
      const size_t b = html.find("base64,", p);
      text.append(html, p, (b == std::string::npos ? html.size() : b) - p);
      if (b == std::string::npos) break;
      p = html.find('"', b);
      if (p == std::string::npos) break;
    }
    EXPECT_EQ(text.find(">nan"), std::string::npos);
    EXPECT_EQ(text.find(" nan"), std::string::npos);
    EXPECT_EQ(text.find(" inf "), std::string::npos);
    EXPECT_EQ(html.find(std::string(POLARCAM_SOURCE_DIR)), std::string::npos);  // no absolute paths
  }
}

INSTANTIATE_TEST_SUITE_P(Ch6, ReportOf,
                         ::testing::Values("circle_inertial", "circle_grinding", "witch_inertial", "witch_grinding",
                                           "limacon_inertial", "limacon_grinding", "serpentine_inertial",
                                           "serpentine_grinding"));

TEST(CliReport, SameInputSameBytes) {
#ifdef POLARCAM_SANITIZED
  GTEST_SKIP() << "a determinism check: the normal build runs it";
#endif
  Scratch sc;
  const std::string a = read_file(make_report(sc, "limacon_inertial"));
  const std::string job = sc.path("ch6/limacon_inertial.toml"), out = sc.path("again.html");
  CliResult r = run_cli("report " + job + " -o " + out + " --map-size 5 --max-evaluations 30 --threads 1");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(a == read_file(out));
}

TEST(CliReport, RendersInHeadlessChromium) {
  const char* chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "chromium is not installed";
  Scratch sc;
  const std::string html = make_report(sc, "witch_grinding");
  const fs::path profile = sc.dir / "chromium-profile", shot = sc.dir / "shot.png";
  fs::create_directories(profile);
  const std::string cmd = std::string("timeout 120 ") + chromium +
                          " --headless --no-sandbox --disable-gpu --disable-background-networking"
                          " --disable-component-update --no-first-run --disable-sync --hide-scrollbars"
                          " --user-data-dir=" + profile.string() + " --screenshot=" + shot.string() +
                          " --window-size=1100,3000 file://" + html + " >" + (sc.dir / "chromium.log").string() +
                          " 2>&1";
  const int st = std::system(cmd.c_str());
  ASSERT_TRUE(fs::exists(shot)) << "status " << st << "\n" << read_file((sc.dir / "chromium.log").string());
  const double ink = ink_fraction(shot.string());
  // text, tables and figures cover a good part of the page; a blank or error page would not
  EXPECT_GT(ink, 0.03) << ink;
  EXPECT_LT(ink, 0.9) << ink;
}

}  // namespace tu_cli_test_cli_optimum
