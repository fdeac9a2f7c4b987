// G-code for sand tables, checked from the G-code alone: a reader written here (G0/G1, G93/G94, X/Y/F words,
// comments) computes each move's duration and the ball's speed along it, which must be within 1 % of the
// requested speed on every move not marked as limited; limited moves keep to the axis limits; the total time is
// the writer's; analytic cases (an arc about the pole, a radial line, a turn at the centre, the coupling); and
// LinuxCNC's standalone interpreter (rs274) accepts every file and moves and feeds as the reader says.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cam/error.hpp"
#include "machine/gcode/gcode.hpp"
#include "tests/rs274.hpp"
#include "tests/temp_path.hpp"

namespace tu_machine_gcode_test_gcode {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

constexpr double kPi = std::numbers::pi;

// ---- the reader -------------------------------------------------------------------------------------------------

struct Move {
  bool rapid = false;
  bool inverse_time = false;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0, f = 0;
  std::string comment;
  double seconds = 0;  // from F: 60 / F in G93, 60 * distance / F in G94
};

struct Program {
  std::vector<Move> moves;  // G0 and G1
  size_t lines = 0;
  bool ends_with_m2 = false;
  std::vector<std::string> problems;  // anything the reader does not accept
};

// Reads a program of G0/G1 moves on axes `ax` and `ay`. Words: G0 G1 G21 G90 G93 G94 M2, axis words and F.
Program read_program(const std::string& text, char ax, char ay) {
  Program p;
  std::istringstream in(text);
  std::string line;
  bool g93 = false, ended = false;
  double x = std::nan(""), y = std::nan("");
  while (std::getline(in, line)) {
    ++p.lines;
    if (ended) p.problems.push_back("a line after M2: " + line);
    std::string comment, code;
    for (size_t i = 0; i < line.size(); ++i) {
      if (line[i] == '(') {
        const size_t e = line.find(')', i);
        if (e == std::string::npos) {
          p.problems.push_back("unclosed comment: " + line);
          break;
        }
        comment += line.substr(i + 1, e - i - 1);
        i = e;
      } else {
        code += line[i];
      }
    }
    std::istringstream words(code);
    std::string w;
    int motion = -1;
    bool has_x = false, has_y = false, has_f = false;
    double nx = x, ny = y, f = 0;
    while (words >> w) {
      const char letter = w[0];
      if (!std::isupper(static_cast<unsigned char>(letter))) p.problems.push_back("not an uppercase word: " + w);
      char* end = nullptr;
      const double value = std::strtod(w.c_str() + 1, &end);
      if (end == w.c_str() + 1 || *end != '\0') p.problems.push_back("not a number: " + w);
      if (letter == 'G') {
        if (w == "G0" || w == "G1") motion = w == "G1";
        else if (w == "G93") g93 = true;
        else if (w == "G94") g93 = false;
        else if (w != "G21" && w != "G90") p.problems.push_back("unexpected code " + w);
      } else if (letter == 'M') {
        if (w == "M2") ended = true;
        else p.problems.push_back("unexpected code " + w);
      } else if (letter == ax) {
        nx = value, has_x = true;
      } else if (letter == ay) {
        ny = value, has_y = true;
      } else if (letter == 'F') {
        f = value, has_f = true;
      } else {
        p.problems.push_back("unexpected word " + w);
      }
    }
    if (motion < 0) {
      if (has_x || has_y || has_f) p.problems.push_back("axis words without a motion: " + line);
      continue;
    }
    Move m;
    m.rapid = motion == 0;
    m.inverse_time = g93;
    m.x0 = x, m.y0 = y, m.x1 = nx, m.y1 = ny, m.f = f;
    m.comment = comment;
    if (!m.rapid) {
      if (!has_f) p.problems.push_back("G1 without F: " + line);
      if (std::isnan(x)) p.problems.push_back("G1 before any position: " + line);
      m.seconds = g93 ? 60.0 / f : 60.0 * std::hypot(nx - x, ny - y) / f;
    }
    x = nx, y = ny;
    p.moves.push_back(m);
  }
  p.ends_with_m2 = ended;
  return p;
}

bool limited(const Move& m) { return m.comment.find("limit") != std::string::npos; }

// The ball's place (theta rad, rho m) at axis positions, from the axis definitions of docs/gcode.md.
struct Ball {
  double theta, rho;
};
Ball ball_at(const GcodeSpec& s, double x, double y) {
  const double th = x / s.theta_units_per_rad;
  return {th, (y - s.coupling * th) / s.rho_units_per_radius * s.table_radius};
}

// The ball speed at fraction t of a move (the axes, so theta and rho, linear in time).
double ball_speed(const GcodeSpec& s, const Move& m, double t) {
  const Ball a = ball_at(s, m.x0, m.y0), b = ball_at(s, m.x1, m.y1);
  const double dth = b.theta - a.theta, drho = b.rho - a.rho, rho = a.rho + t * drho;
  return std::sqrt(drho * drho + rho * rho * dth * dth) / m.seconds;
}

// Everything the reader can check of a program against its spec, speed and the writer's statistics.
Program check_program(const std::string& text, const GcodeSpec& s, double V, const GcodeStats& st,
                      const std::vector<ThetaRho>& v) {
  Program p = read_program(text, s.theta_axis[0], s.rho_axis[0]);
  for (const std::string& e : p.problems) ADD_FAILURE() << e;
  EXPECT_TRUE(p.ends_with_m2);
  EXPECT_EQ(p.lines, st.lines);
  size_t g1 = 0, lim = 0;
  double total = 0, worst = 0;
  const double q = std::pow(10.0, -s.decimals);
  for (const Move& m : p.moves) {
    if (m.rapid) continue;
    ++g1;
    total += m.seconds;
    EXPECT_EQ(m.inverse_time, s.feed_mode == FeedMode::inverse_time);
    const double minutes = m.seconds / 60.0;
    const double rate_x = std::abs(m.x1 - m.x0) / minutes, rate_y = std::abs(m.y1 - m.y0) / minutes;
    if (limited(m)) {
      ++lim;
      // within the limits, up to the rounding of F
      EXPECT_LE(rate_x, s.theta_max_feed * (1 + 1e-12)) << m.comment;
      EXPECT_LE(rate_y, s.rho_max_feed * (1 + 1e-12)) << m.comment;
      if (m.comment.find("axis limit") != std::string::npos) {  // and at one of them
        EXPECT_GE(std::max(rate_x / s.theta_max_feed, rate_y / s.rho_max_feed), 1 - 1e-3) << m.comment;
      }
    } else {
      EXPECT_LE(rate_x, s.theta_max_feed * (1 + 1e-12));
      EXPECT_LE(rate_y, s.rho_max_feed * (1 + 1e-12));
      if (s.feed_mode == FeedMode::inverse_time)
        for (int i = 0; i <= 10; ++i) {
          const double e = std::abs(ball_speed(s, m, i / 10.0) / V - 1.0);
          worst = std::max(worst, e);
          EXPECT_LE(e, 0.01) << "G1 to " << m.x1 << " " << m.y1 << " F" << m.f;
        }
    }
  }
  EXPECT_EQ(g1, st.g1);
  EXPECT_EQ(lim, st.limited);
  EXPECT_NEAR(total, st.duration_s, 1e-9 * st.duration_s);
  if (s.feed_mode == FeedMode::inverse_time) {
    EXPECT_NEAR(worst * 100, st.max_speed_error_pct, 1e-6);
  }
  // the moves pass through every vertex, in order, and in between stay on the vertices' theta-rho segments
  size_t k = 0;
  const double tol_th = q / std::abs(s.theta_units_per_rad);
  for (const Move& m : p.moves) {
    const Ball b = ball_at(s, m.x1, m.y1);
    auto at = [&](size_t i) {
      return std::abs(b.theta - v[i].theta) <= tol_th && std::abs(b.rho - v[i].rho) <= 2 * q * s.table_radius;
    };
    while (k + 1 < v.size() && at(k + 1)) ++k;
    if (m.rapid) {
      EXPECT_TRUE(at(0));
      continue;
    }
    if (at(k)) continue;
    if (k + 1 >= v.size()) {
      ADD_FAILURE() << "a move beyond the last vertex";
      break;
    }
    const ThetaRho a = v[k], c = v[k + 1];
    // on the segment: rho - rho_a = (theta - theta_a) (rho_c - rho_a) / (theta_c - theta_a)
    const double f = (b.theta - a.theta) / (c.theta - a.theta);
    EXPECT_GT(f, 0.0);
    EXPECT_LT(f, 1.0);
    EXPECT_NEAR(b.rho, a.rho + f * (c.rho - a.rho), 2 * q * s.table_radius + std::abs(s.coupling) * tol_th);
  }
  EXPECT_EQ(k + 1, v.size()) << "the moves do not reach the last vertex";
  return p;
}

std::string write(const std::vector<ThetaRho>& v, const GcodeSpec& s, double V, GcodeStats& st) {
  std::ostringstream o;
  st = write_gcode(o, v, s, V, {"test (pattern)"});
  return o.str();
}

// ---- patterns and specs -----------------------------------------------------------------------------------------

constexpr double kR = 0.2;  // table radius, m

// A sand-table pattern as a .thr would give it (rho in metres): the arm turns at the centre, a spiral of 8 turns
// out to the rim in steps of 0.2 rad, a circle at the rim, straight in to the centre, and out again to half radius.
std::vector<ThetaRho> pattern() {
  std::vector<ThetaRho> v{{0.0, 0.0}, {kPi, 0.0}};
  const double turns = 16 * kPi;
  for (double th = 0.2; th < turns - 1e-9; th += 0.2) v.push_back({kPi + th, kR * th / turns});
  v.push_back({kPi + turns, kR});
  v.push_back({kPi + turns + 2 * kPi, kR});
  v.push_back({kPi + turns + 2 * kPi, 0.0});
  v.push_back({kPi + turns + 2 * kPi + 0.5, 0.5 * kR});
  return v;
}

GcodeSpec spec(FeedMode mode, double coupling) {
  GcodeSpec s;
  s.theta_units_per_rad = 1.0;
  s.rho_units_per_radius = 200.0;  // mm
  s.table_radius = kR;
  s.coupling = coupling;
  s.theta_max_feed = 60.0;   // rad/min: 1 rad/s
  s.rho_max_feed = 1200.0;   // mm/min
  s.feed_mode = mode;
  s.axis_feed = 100.0;
  s.decimals = 4;
  return s;
}

// rs274 on a program: its exit status, its output (the canonical calls) and its error output.
using Rs274 = test::Rs274Run;
Rs274 run_rs274(const std::string& program, const std::string& name) {
  const std::string file = test::temp_path(name + ".ngc");
  std::ofstream(file) << program;
  Rs274 r = test::run_rs274(file);
  std::remove(file.c_str());
  return r;
}

}  // namespace

// ---- tests ------------------------------------------------------------------------------------------------------

TEST(Gcode, InverseTimeKeepsTheBallSpeedWithinOnePercent) {
  for (double coupling : {0.0, 25.0}) {
    SCOPED_TRACE("coupling " + std::to_string(coupling));
    const GcodeSpec s = spec(FeedMode::inverse_time, coupling);
    const double V = 0.02;
    GcodeStats st;
    const std::string g = write(pattern(), s, V, st);
    check_program(g, s, V, st, pattern());
    EXPECT_LE(st.max_speed_error_pct, 1.0);
    EXPECT_GT(st.g1, pattern().size());  // the spiral's segments near the centre are split
    EXPECT_EQ(st.centre_turns, 1u);
    // near the centre the theta axis limit binds (1 rad/s is 20 mm/s at 20 mm); most moves are at the ball speed
    EXPECT_GT(st.g1 - st.limited, st.g1 / 2);
    std::printf("  coupling %g: %zu lines, %zu G1, %zu limited, %.3f s, speed error %.3f %%\n", coupling, st.lines,
                st.g1, st.limited, st.duration_s, st.max_speed_error_pct);
  }
}

TEST(Gcode, AxisLimitsSlowTheMovesThatNeedIt) {
  // at 0.3 m/s the ball would turn the arm at 1.5 rad/s at the rim, over the theta axis's 1 rad/s
  const GcodeSpec s = spec(FeedMode::inverse_time, 0.0);
  const double V = 0.3;
  GcodeStats st;
  const std::string g = write(pattern(), s, V, st);
  const Program p = check_program(g, s, V, st, pattern());
  EXPECT_GT(st.limited, 10u);
  // the circle at the rim: one move of 2 pi at the theta limit, 2 pi rad / (60 rad/min) = 6.283 s
  bool found = false;
  for (const Move& m : p.moves)
    if (!m.rapid && std::abs(m.x1 - m.x0 - 2 * kPi) < 1e-3 && std::abs(m.y1 - m.y0) < 1e-3) {
      found = true;
      EXPECT_NE(m.comment.find("axis limit: X"), std::string::npos);
      EXPECT_NEAR(m.seconds, 2 * kPi, 1e-3);
    }
  EXPECT_TRUE(found);
}

TEST(Gcode, AnalyticMoves) {
  const GcodeSpec s = spec(FeedMode::inverse_time, 0.0);
  const double V = 0.01;
  // an arc about the pole at half radius: the speed is constant, one move of length 0.1 m * 2 pi
  {
    GcodeStats st;
    const std::string g = write({{0.0, 0.1}, {2 * kPi, 0.1}}, s, V, st);
    EXPECT_NE(g.find("G1 X6.2832 Y100.0000 F"), std::string::npos) << g;
    EXPECT_EQ(st.g1, 1u);
    EXPECT_NEAR(st.duration_s, 0.1 * 2 * kPi / V, 1e-4 * 0.1 * 2 * kPi / V);
  }
  // a radial line from 20 mm to 180 mm: one move, 0.16 m at V
  {
    GcodeStats st;
    const std::string g = write({{1.0, 0.02}, {1.0, 0.18}}, s, V, st);
    EXPECT_NE(g.find("G0 X1.0000 Y20.0000"), std::string::npos) << g;
    EXPECT_NE(g.find("G1 X1.0000 Y180.0000 F3.7500"), std::string::npos) << g;  // 16 s = 0.26667 min
    EXPECT_NEAR(st.duration_s, 16.0, 1e-9);
  }
  // the arm turning half a turn at the centre: timed by the theta limit, 3.1416 (as printed) / (60 rad/min)
  {
    GcodeStats st;
    const std::string g = write({{0.0, 0.0}, {kPi, 0.0}}, s, V, st);
    EXPECT_NE(g.find("G1 X3.1416 Y0.0000 F19.0985 (axis limit: X, ball at the centre)"), std::string::npos) << g;
    EXPECT_EQ(st.centre_turns, 1u);
    EXPECT_EQ(st.limited, 1u);
  }
}

TEST(Gcode, CouplingIsAddedToTheRadialAxis) {
  // An arc about the pole at half radius with coupling c: the radial axis must travel c per radian while the
  // ball stays at rho, Y = 200 mm * 0.5 + c theta; the ball speed is that of the arc.
  const double c = 3.0, V = 0.01;
  GcodeSpec s = spec(FeedMode::inverse_time, c);
  {
    GcodeStats st;
    const std::string g = write({{0.0, 0.1}, {2 * kPi, 0.1}}, s, V, st);
    EXPECT_NE(g.find("G0 X0.0000 Y100.0000"), std::string::npos) << g;
    EXPECT_NE(g.find("G1 X6.2832 Y118.8496 F"), std::string::npos) << g;  // 100 + 3 * 2 pi
    EXPECT_NEAR(st.duration_s, 0.1 * 2 * kPi / V, 1e-4 * 0.1 * 2 * kPi / V);
    EXPECT_EQ(st.limited, 0u);
  }
  // with the radial axis limited to 15 mm/min, the coupling's 3 mm/rad make it bind: 3 * 2 pi / 15 min (75.4 s,
  // longer than the ball's 62.8 s)
  s.rho_max_feed = 15.0;
  {
    GcodeStats st;
    const std::string g = write({{0.0, 0.1}, {2 * kPi, 0.1}}, s, V, st);
    EXPECT_NE(g.find("(axis limit: Y)"), std::string::npos) << g;
    EXPECT_NEAR(st.duration_s, 60.0 * 3 * 2 * kPi / 15.0, 1e-4 * 75.4);
  }
  // a negative coupling subtracts
  s = spec(FeedMode::inverse_time, -3.0);
  GcodeStats st;
  EXPECT_NE(write({{0.0, 0.1}, {2 * kPi, 0.1}}, s, V, st).find("G1 X6.2832 Y81.1504 F"), std::string::npos);
}

TEST(Gcode, AxisModeHasAConstantFeed) {
  for (double coupling : {0.0, 25.0}) {
    SCOPED_TRACE("coupling " + std::to_string(coupling));
    const GcodeSpec s = spec(FeedMode::axis, coupling);
    const double V = 0.02;
    GcodeStats st;
    const std::string g = write(pattern(), s, V, st);
    const Program p = check_program(g, s, V, st, pattern());
    EXPECT_NE(g.find("G94"), std::string::npos);
    EXPECT_EQ(g.find("G93"), std::string::npos);
    for (const Move& m : p.moves)
      if (!m.rapid && !limited(m)) {
        EXPECT_EQ(m.f, 100.0);
      }
    // a constant axis feed: one G1 per segment, and the ball is slow at the centre, fast at the rim
    EXPECT_EQ(st.g1, pattern().size() - 1);
    EXPECT_GT(st.ball_speed_max_mps / st.ball_speed_min_mps, 5.0);
    std::printf("  axis mode, coupling %g: ball %.4f .. %.4f m/s, speed error %.1f %%\n", coupling,
                st.ball_speed_min_mps, st.ball_speed_max_mps, st.max_speed_error_pct);
  }
}

TEST(Gcode, SameInputSameBytes) {
  const GcodeSpec s = spec(FeedMode::inverse_time, 25.0);
  GcodeStats a, b;
  EXPECT_EQ(write(pattern(), s, 0.02, a), write(pattern(), s, 0.02, b));
}

TEST(Gcode, HeaderFooterAndAxisLetters) {
  GcodeSpec s = spec(FeedMode::inverse_time, 0.0);
  s.theta_axis = "A";
  s.rho_axis = "X";
  s.header = {"G21", "G90", "G17"};
  s.footer = {"G0 X0"};
  GcodeStats st;
  const std::string g = write({{0.0, 0.1}, {1.0, 0.15}}, s, 0.01, st);
  EXPECT_EQ(g.rfind("(test pattern)\nG21\nG90\nG17\nG93\nG0 A0.0000 X100.0000 (to the start)\nG1 A0.0436 X102.1803 F", 0), 0u) << g;
  EXPECT_NE(g.find("G1 A1.0000 X150.0000 F"), std::string::npos);
  EXPECT_NE(g.find("\nG94\nG0 X0\nM2\n"), std::string::npos) << g;
}

TEST(Gcode, RefusesBadInput) {
  const std::vector<ThetaRho> v{{0.0, 0.1}, {1.0, 0.15}};
  auto place_of = [&](const GcodeSpec& s, const std::vector<ThetaRho>& pts, double V) -> std::string {
    std::ostringstream o;
    try {
      write_gcode(o, pts, s, V);
    } catch (const InputError& e) {
      EXPECT_EQ(o.str(), "");  // nothing written when refused
      return e.place().empty() ? e.message() : e.place();
    }
    return "accepted";
  };
  GcodeSpec s = spec(FeedMode::inverse_time, 0.0);
  EXPECT_EQ(place_of(s, v, 0.01), "accepted");
  s.theta_axis = "Q";
  EXPECT_EQ(place_of(s, v, 0.01), "theta_axis");
  s = spec(FeedMode::inverse_time, 0.0);
  s.rho_axis = "X";
  EXPECT_EQ(place_of(s, v, 0.01), "rho_axis");
  s = spec(FeedMode::inverse_time, 0.0);
  s.theta_max_feed = 0;
  EXPECT_EQ(place_of(s, v, 0.01), "theta_max_feed");
  s = spec(FeedMode::axis, 0.0);
  s.axis_feed = 0;
  EXPECT_EQ(place_of(s, v, 0.01), "axis_feed");
  s = spec(FeedMode::inverse_time, 0.0);
  s.header = {"G21\nG91"};
  EXPECT_EQ(place_of(s, v, 0.01), "header");
  s = spec(FeedMode::inverse_time, 0.0);
  EXPECT_EQ(place_of(s, {{0.0, 0.1}, {1.0, 0.25}}, 0.01), "point 2");  // beyond the 200 mm table
}

TEST(Gcode, LinuxCncInterpreterAcceptsEveryFile) {
  ASSERT_STRNE(POLARCAM_RS274, "") << "rs274 (Debian package linuxcnc-uspace) is needed for this test";
  struct Case {
    const char* name;
    FeedMode mode;
    double coupling;
    double V;
  };
  const Case cases[] = {{"inverse-time", FeedMode::inverse_time, 0.0, 0.02},
                        {"inverse-time-coupled", FeedMode::inverse_time, 25.0, 0.3},
                        {"axis", FeedMode::axis, 0.0, 0.02},
                        {"axis-coupled", FeedMode::axis, 25.0, 0.02}};
  const std::regex feed(R"(SET_FEED_RATE\(([-0-9.]+)\))");
  const std::regex straight(R"(STRAIGHT_(FEED|TRAVERSE)\(([-0-9.]+), ([-0-9.]+),)");
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const GcodeSpec s = spec(c.mode, c.coupling);
    GcodeStats st;
    const std::string g = write(pattern(), s, c.V, st);
    const Program p = read_program(g, 'X', 'Y');
    const Rs274 r = run_rs274(g, c.name);
    EXPECT_EQ(r.status, 0) << r.err;
    for (const std::string& text : {r.out, r.err}) {
      std::string lower = text;
      for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      EXPECT_EQ(lower.find("error"), std::string::npos) << text.substr(0, 2000);
    }
    EXPECT_NE(r.out.find("PROGRAM_END()"), std::string::npos);
    // the interpreter's moves and feed rates, in order, against the reader's
    std::istringstream in(r.out);
    std::string line;
    double rate = 0;
    size_t i = 0;
    while (std::getline(in, line)) {
      std::smatch m;
      if (std::regex_search(line, m, feed)) rate = std::stod(m[1]);
      if (!std::regex_search(line, m, straight)) continue;
      ASSERT_LT(i, p.moves.size());
      const Move& mv = p.moves[i++];
      EXPECT_EQ(m[1] == "TRAVERSE", mv.rapid);
      EXPECT_NEAR(std::stod(m[2]), mv.x1, 1e-4);
      EXPECT_NEAR(std::stod(m[3]), mv.y1, 1e-4);
      if (!mv.rapid) {
        // its feed rate in units per minute: the move's length over its duration
        const double expected = std::hypot(mv.x1 - mv.x0, mv.y1 - mv.y0) / (mv.seconds / 60.0);
        EXPECT_NEAR(rate, expected, 1e-4 + 1e-4 * expected) << line;
      }
    }
    EXPECT_EQ(i, p.moves.size());
  }
}

TEST(Gcode, LiftingProgramLiftsAroundEachRapidAndLinuxCncAcceptsIt) {
  ASSERT_STRNE(POLARCAM_RS274, "") << "rs274 (Debian package linuxcnc-uspace) is needed for this test";
  // three strokes: an arc about the pole, a radial line, a spiral piece
  const std::vector<std::vector<ThetaRho>> strokes{{{0.0, 0.05}, {1.0, 0.05}},
                                                   {{2.0, 0.08}, {2.0, 0.15}},
                                                   {{3.0, 0.10}, {3.5, 0.12}, {4.0, 0.14}}};
  for (const auto& words : {std::pair<std::vector<std::string>, std::vector<std::string>>{{"M5"}, {"M3"}},
                            std::pair<std::vector<std::string>, std::vector<std::string>>{{"G0 Z5"}, {"G1 Z-1 F100"}}}) {
    GcodeSpec s = spec(FeedMode::inverse_time, 0.0);
    s.pen_up = words.first;
    s.pen_down = words.second;
    SCOPED_TRACE(s.pen_up.front());
    std::ostringstream o;
    const GcodeStats st = write_gcode_lifting(o, strokes, s, 0.02, {"lifting test"});
    const std::string g = o.str();
    EXPECT_EQ(st.pen_ups, 4u);
    EXPECT_EQ(st.pen_downs, 3u);
    EXPECT_EQ(st.rapids, 2u);
    // line by line: each G0 between a lift and a lowering, no G1 of the strokes with the tool up
    std::istringstream in(g);
    bool up = false;
    size_t g0 = 0, ups = 0, downs = 0, g1_xy = 0;
    for (std::string l; std::getline(in, l);) {
      if (l == s.pen_up.front()) {
        up = true;
        ++ups;
      } else if (l == s.pen_down.front()) {
        up = false;
        ++downs;
      } else if (l.rfind("G0 X", 0) == 0) {
        ++g0;
        EXPECT_TRUE(up) << l;
      } else if (l.rfind("G1 X", 0) == 0) {
        ++g1_xy;
        EXPECT_FALSE(up) << l;
      }
    }
    EXPECT_EQ(ups, 4u);
    EXPECT_EQ(downs, 3u);
    EXPECT_EQ(g0, 3u);
    EXPECT_EQ(g1_xy, st.g1);
    EXPECT_TRUE(up);
    // the G0 targets are the strokes' starts in axis units (X = theta, Y = rho in mm)
    const Program p = read_program(g, 'X', 'Y');
    std::vector<const Move*> rapids;
    for (const Move& m : p.moves)
      if (m.rapid && !m.comment.empty()) rapids.push_back(&m);  // the G0s to the strokes (not a pen word's)
    ASSERT_EQ(rapids.size(), 3u);
    for (size_t k = 0; k < 3; ++k) {
      EXPECT_NEAR(rapids[k]->x1, strokes[k].front().theta, 1e-4);
      EXPECT_NEAR(rapids[k]->y1, strokes[k].front().rho * 1e3, 1e-4);
    }
    const Rs274 r = run_rs274(g, "lifting");
    EXPECT_EQ(r.status, 0) << r.err;
    for (const std::string& text : {r.out, r.err}) {
      std::string lower = text;
      for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
      EXPECT_EQ(lower.find("error"), std::string::npos) << text.substr(0, 2000);
    }
    auto count = [&](const std::string& what) {
      size_t n = 0;
      for (size_t q = r.out.find(what); q != std::string::npos; q = r.out.find(what, q + 1)) ++n;
      return n;
    };
    if (s.pen_up.front() == "M5") {
      EXPECT_EQ(count("STOP_SPINDLE_TURNING("), 4u + 1u);  // the lifts, and M2's own stop of the spindle
      EXPECT_EQ(count("START_SPINDLE_CLOCKWISE("), 3u);
      EXPECT_EQ(count("STRAIGHT_TRAVERSE("), 3u);
    } else {
      EXPECT_EQ(count("STRAIGHT_TRAVERSE("), 3u + 4u);  // the rapids and the Z lifts
    }
  }
  // a pen word that is not one printable line is refused naming its key
  GcodeSpec s = spec(FeedMode::inverse_time, 0.0);
  s.pen_down = {"M3\nM5"};
  std::ostringstream o;
  try {
    write_gcode_lifting(o, strokes, s, 0.02);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "pen_down");
  }
}

}  // namespace tu_machine_gcode_test_gcode
