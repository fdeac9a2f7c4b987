// Multi-contour jobs on a machine that lifts its tool (examples/machines/pen-plotter.toml, the logo's four
// contours): the tape (version 2, tool events alternating, steps adding up), a single contour's tape unchanged, the
// exports (G-code lifts accepted by LinuxCNC's rs274, the SVG's dashed rapids, the theta-rho file refused), the
// preview, and the readers that refuse tool events in one line.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli_runner.hpp"
#include "tests/rs274.hpp"

namespace tu_cli_test_cli_penup {  // the test files of a program compile together (unity build)

using namespace polarcam::test;

namespace {

const std::string kSrc = std::string(POLARCAM_SOURCE_DIR);
const std::string kPlotter = kSrc + "/examples/machines/pen-plotter.toml";
const std::string kLogo = kSrc + "/examples/patterns/logo.svg";
const std::string kPattern = kLogo + " --machine " + kPlotter + " --speed \"20 mm/s\"";
// for the commands whose result does not depend on the speed (an SVG or .thr export, the error metrics)
const std::string kDrawing = kLogo + " --machine " + kPlotter;

uint32_t file_crc(const std::string& p) {
  const std::string b = read_file(p);
  return static_cast<uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(b.data()), static_cast<uInt>(b.size())));
}

size_t count_lines(const std::string& text, const std::string& line) {
  std::istringstream in(text);
  std::string l;
  size_t n = 0;
  while (std::getline(in, l)) n += l == line;
  return n;
}

}  // namespace

TEST(CliPenUp, LiftingJobTapeHasAlternatingToolEventsAndItsStepsAddUp) {
  Scratch sc;
  const std::string tape = sc.path("logo.tape");
  const auto d = cli_json("digitize " + kPattern + " -o " + tape + " --json");
  EXPECT_EQ(d["contours"], 4);
  EXPECT_EQ(d["tool_lift"], true);
  EXPECT_EQ(d["tool_events"], 6);
  EXPECT_EQ(d["rapid_moves"], 3);
  EXPECT_GT(d["rapid_length_m"].get<double>(), 0.0);
  EXPECT_GT(d["rapid_steps"].get<uint64_t>(), 0u);
  // 100 mm/s along the rapids
  EXPECT_NEAR(d["rapid_time_s"].get<double>(), d["rapid_length_m"].get<double>() / 0.1, 1e-6);
  EXPECT_NEAR(d["path_length_m"].get<double>(), d["drawn_length_m"].get<double>() + d["rapid_length_m"].get<double>(), 1e-9);
  const auto h = cli_json("inspect " + tape + " --json");
  EXPECT_EQ(h["format_version"], 2);
  EXPECT_EQ(h["tool_events"], 6);
  EXPECT_EQ(h["tool_starts"], "down");
  EXPECT_EQ(h["steps_total"], d["steps_total"]);
  // every row of the listing: the steps add up to the end node less the start node, the events alternate from
  // down (the first is "up"), three of each, between steps (never first or last), and time never runs back
  const CliResult csv = run_cli("inspect " + tape + " --csv");
  ASSERT_EQ(csv.code, 0) << csv.err;
  std::istringstream in(csv.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t_ns,axis,dir,n,m");
  int64_t sum[2] = {0, 0}, last_t = 0;
  uint64_t steps = 0, rapid_steps = 0;
  std::vector<std::string> events;
  bool up = false;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
    ASSERT_EQ(f.size(), 5u) << line;
    const int64_t t = std::stoll(f[0]);
    EXPECT_GE(t, last_t);
    last_t = t;
    if (f[1] == "tool") {
      ASSERT_TRUE(f[2] == "up" || f[2] == "down") << line;
      EXPECT_EQ(f[2] == "up", !up) << "events must alternate: " << line;
      up = f[2] == "up";
      EXPECT_GT(steps, 0u) << "an event before the first step";
      events.push_back(f[2]);
      continue;
    }
    const int axis = f[1] == "r" ? 0 : 1;
    sum[axis] += std::stoi(f[2]);
    ++steps;
    if (up) ++rapid_steps;
  }
  EXPECT_FALSE(up) << "the tape ends with the tool down";
  EXPECT_EQ(events, (std::vector<std::string>{"up", "down", "up", "down", "up", "down"}));
  EXPECT_EQ(steps, h["steps_total"].get<uint64_t>());
  EXPECT_EQ(rapid_steps, d["rapid_steps"].get<uint64_t>());
  for (int a = 0; a < 2; ++a)
    EXPECT_EQ(sum[a], h["end_node"][a].get<int64_t>() - h["start_node"][a].get<int64_t>()) << "axis " << a;
}

TEST(CliPenUp, TapesWithoutToolEventsAreUnchanged) {
  Scratch sc;
  // the limacon example's tape, byte for byte as it was before tool events existed (CRC-32 of the whole file)
  const std::string lim = sc.path("limacon.tape");
  ASSERT_EQ(run_cli("digitize " + kSrc + "/examples/limacon.toml -o " + lim).code, 0);
  EXPECT_EQ(file_crc(lim), 0x12ec9c92u);
  // the logo on the sand table: its contours joined by drawn moves, as before
  const std::string sand = sc.path("logo-sand.tape");
  ASSERT_EQ(run_cli("digitize " + kLogo + " --machine " + kSrc + "/examples/machines/sand-table.toml --speed \"40 mm/s\" -o " + sand).code, 0);
  EXPECT_EQ(file_crc(sand), 0xee1ff63cu);
  // one contour on the lifting machine: a version 1 tape with the records of the same machine without the lift
  const std::string ring = sc.write("ring.svg",
                                    "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"80mm\" height=\"80mm\" viewBox=\"0 0 100 100\">"
                                    "<circle cx=\"50\" cy=\"50\" r=\"45\" fill=\"none\" stroke=\"black\"/></svg>\n");
  const std::string nolift = sc.write("nolift.toml", replace(read_file(kPlotter), "tool_lift = true", "tool_lift = false"));
  const std::string a = sc.path("a.tape"), b = sc.path("b.tape");
  ASSERT_EQ(run_cli("digitize " + ring + " --machine " + kPlotter + " --speed \"20 mm/s\" -o " + a).code, 0);
  ASSERT_EQ(run_cli("digitize " + ring + " --machine " + nolift + " --speed \"20 mm/s\" -o " + b).code, 0);
  const auto ha = cli_json("inspect " + a + " --json"), hb = cli_json("inspect " + b + " --json");
  EXPECT_EQ(ha["format_version"], 1);
  EXPECT_EQ(hb["format_version"], 1);
  EXPECT_FALSE(ha.contains("tool_events"));
  EXPECT_EQ(ha["records_crc32"], hb["records_crc32"]);
  EXPECT_EQ(ha["steps_total"], hb["steps_total"]);
}

TEST(CliPenUp, GcodeLiftsTheToolAroundEachRapidAndLinuxCncAcceptsIt) {
  Scratch sc;
  const std::string out = sc.path("logo.ngc");
  const auto j = cli_json("export " + kPattern + " --format gcode -o " + out + " --json");
  EXPECT_EQ(j["contours"], 4);
  EXPECT_EQ(j["tool_lift"], true);
  EXPECT_EQ(j["pen_downs"], 4);
  EXPECT_EQ(j["pen_ups"], 5);
  EXPECT_EQ(j["rapids"], 3);
  const std::string g = read_file(out);
  // the machine file's words: M5 lifts, "M3 S1000" and "G4 P0.2" lower; every G0 between a lift and a lowering
  EXPECT_EQ(count_lines(g, "M5"), 5u);
  EXPECT_EQ(count_lines(g, "M3 S1000"), 4u);
  EXPECT_EQ(count_lines(g, "G4 P0.2"), 4u);
  std::vector<std::string> lines;
  {
    std::istringstream in(g);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  size_t g0 = 0;
  bool tool_up = false;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (lines[i] == "M5") tool_up = true;
    if (lines[i] == "M3 S1000") tool_up = false;
    if (lines[i].rfind("G0 ", 0) == 0) {
      ++g0;
      EXPECT_TRUE(tool_up) << "a G0 with the tool down, line " << i + 1;
      ASSERT_LT(i + 1, lines.size());
      EXPECT_EQ(lines[i + 1], "M3 S1000") << "the tool is lowered right after the rapid, line " << i + 2;
    }
    if (lines[i].rfind("G1 ", 0) == 0) {
      EXPECT_FALSE(tool_up) << "a G1 with the tool up, line " << i + 1;
    }
  }
  EXPECT_EQ(g0, 4u);
  EXPECT_TRUE(tool_up) << "the tool is lifted at the end";
  ASSERT_STRNE(POLARCAM_RS274, "") << "rs274 (Debian package linuxcnc-uspace) is needed for this test";
  const Rs274Run r = run_rs274(out);
  const std::string canon = r.out + r.err;
  EXPECT_EQ(r.status, 0) << canon.substr(0, 2000);
  std::string lower = canon;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  EXPECT_EQ(lower.find("error"), std::string::npos) << canon.substr(0, 2000);
  // the interpreter's own calls: four traverses, the spindle stopped five times (and once more by M2) and started
  // four
  auto count = [&](const std::string& what) {
    size_t n = 0;
    for (size_t p = canon.find(what); p != std::string::npos; p = canon.find(what, p + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("STRAIGHT_TRAVERSE("), 4u);
  EXPECT_EQ(count("STOP_SPINDLE_TURNING("), 5u + 1u);
  EXPECT_EQ(count("START_SPINDLE_CLOCKWISE("), 4u);
}

TEST(CliPenUp, SvgAndPreviewDrawTheRapidsDashed) {
  Scratch sc;
  const std::string svg = sc.path("logo.svg");
  cli_json("export " + kDrawing + " --format svg -o " + svg + " --json");
  const std::string s = read_file(svg);
  const size_t conn = s.find("<g id=\"connecting\""), path = s.find("<g id=\"path\"");
  ASSERT_NE(conn, std::string::npos);
  ASSERT_NE(path, std::string::npos);
  const std::string connecting = s.substr(conn, path - conn), drawn = s.substr(path);
  EXPECT_NE(connecting.find("stroke-dasharray"), std::string::npos);
  auto polylines = [](const std::string& t) {
    size_t n = 0;
    for (size_t p = t.find("<polyline"); p != std::string::npos; p = t.find("<polyline", p + 1)) ++n;
    return n;
  };
  EXPECT_EQ(polylines(connecting), 3u);
  EXPECT_EQ(polylines(drawn), 4u);
  // the preview of the job and of its tape: three runs with the tool up, four drawn
  const std::string tape = sc.path("logo.tape");
  ASSERT_EQ(run_cli("digitize " + kPattern + " -o " + tape).code, 0);
  for (const std::string& in : {kPattern, tape}) {
    const auto j = cli_json("preview " + in + " -o " + sc.path("p.svg") + " --json");
    EXPECT_EQ(j["rapid_moves"], 3) << in;
    EXPECT_GT(j["rapid_points"].get<size_t>(), 3u) << in;
  }
}

TEST(CliPenUp, ReadersThatCannotTakeToolEventsRefuseInOneLine) {
  Scratch sc;
  const std::string tape = sc.path("logo.tape");
  ASSERT_EQ(run_cli("digitize " + kPattern + " -o " + tape).code, 0);
  expect_one_line_error(run_cli("error " + tape + " --job " + kDrawing), "lifts its tool");
  expect_one_line_error(run_cli("compare " + kPattern), "lifts its tool");
  const std::string thr = sc.path("logo.thr");
  const CliResult r = run_cli("export " + kDrawing + " --format thr -o " + thr);
  expect_refused(r, sc, thr, "cannot lift the tool");
}

}  // namespace tu_cli_test_cli_penup
