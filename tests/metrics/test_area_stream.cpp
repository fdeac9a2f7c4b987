// The streamed mode of the area and error meters (metrics/area_error.hpp, metrics/error_metrics.hpp): the same
// numbers as the recorded mode, in a window of sectors that does not grow with the tape; and the fall-back when
// the staircase comes back to a sector measured already.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

#include "tests/area_helpers.hpp"
#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "metrics/error_metrics.hpp"

namespace tu_metrics_test_area_stream {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {

constexpr double kPi = std::numbers::pi;

ToolPathPtr placed(CurvePtr c, double C, double beta) {
  return make_tool_path(std::move(c), Placement{C, beta}, ToolSpec{}, TravelSpec{});
}

AreaErrorResult streamed(const AreaRun& r, const Grid& g, const std::vector<Recorded>& steps, bool* ok,
                         size_t* window = nullptr) {
  PolarAreaMeter m;
  m.reset(r.track, g);
  m.stream_from(r.dig.start_n, r.dig.start_m);
  for (const auto& s : steps) m.record(s.axis, s.dir);
  const AreaErrorResult a = m.finish(r.dig.start_n, r.dig.start_m);
  *ok = m.streamed();
  if (window) *window = m.peak_window();
  return a;
}

}  // namespace

// A circle about the machine pole: the annulus pi |R^2 - (n dR)^2| (n the node radius of the staircase), streamed.
TEST(AreaStream, CircleAboutThePoleIsAnAnnulus) {
  const Grid g = coarse_grid(1e-3, 720);
  const double R = 50.3e-3;
  auto path = placed(make_circle({0, 0}, R), 0.0, 0.0);
  AreaRun r = area_run(*path, g, StepRule::nearest);
  bool ok = false;
  const AreaErrorResult a = streamed(r, g, r.steps, &ok);
  ASSERT_TRUE(ok);
  const double rho = 50e-3;  // the nearest radial level
  EXPECT_NEAR(a.area_m2, kPi * (R * R - rho * rho), 1e-12 * kPi * R * R);
}

// The thesis's contours at the thesis's resolution and 10x finer, both rules: area, sector counts and the whole
// error report equal to the recorded mode's, and at most a few hundred sectors held at once. The serpentine near
// the pole is crossed twice by some rays from the pole: the streamed meter gives up on it (the recorded mode then
// measures it).
TEST(AreaStream, SameAsRecordedInAWindowThatDoesNotGrow) {
  struct Case {
    const char* name;
    ToolPathPtr path;
    int streams;  // 1: streams; 0: the contour covers some angles twice (seen from the pole), the meter gives up;
                  // -1: either (rays from an outside pole cross a circle twice, but its far side comes back late)
  };
  std::vector<Case> cases = {
      {"limacon, pole inside", placed(make_limacon(0.0508, 0.0762), 0.0127, 0.0), 1},
      {"witch", placed(make_witch(0.2159, -0.2032, 0.2032), 0.1546, 1.236), 1},
      {"circle, pole outside", placed(make_circle({0, 0}, 0.0508), 0.2032, 1.5 * kPi), -1},
      {"serpentine near the pole", placed(make_serpentine(0.0127, 0.0762, -0.0762, 0.0762), 0.0537, 4.247), 0},
  };
  for (const auto& c : cases) {
    for (int finer : {1, 10}) {
      const Grid g = coarse_grid(0.0254e-3 / finer, 16000 * finer);
      for (StepRule rule : {StepRule::nearest, StepRule::thesis}) {
        const std::string what = std::string(c.name) + ", " + std::to_string(finer) + "x, " + to_string(rule);
        AreaRun r = area_run(*c.path, g, rule);
        bool ok = false;
        size_t window = 0;
        const AreaErrorResult a = streamed(r, g, r.steps, &ok, &window);
        EXPECT_LT(window, 5u * kStreamWindow) << what << " (" << r.area.sectors << " sectors)";
        if (c.streams >= 0) {
          ASSERT_EQ(ok, c.streams == 1) << what;
        }
        if (!ok) continue;
        EXPECT_EQ(a.area_m2, r.area.area_m2) << what;
        EXPECT_EQ(a.sectors, r.area.sectors) << what;
        EXPECT_EQ(a.general_sectors, r.area.general_sectors) << what;
        EXPECT_EQ(a.run_steps, r.area.run_steps) << what;
        EXPECT_EQ(a.rise_steps, r.area.rise_steps) << what;
        if (finer == 10) {
          // the error meters, streamed and recorded, on one thread and with the deviation on a second one
          ErrorMeters rec, str, rec2, str2;
          for (ErrorMeters* m : {&rec, &str, &rec2, &str2}) m->reset(*c.path, r.track, g, 100);
          rec2.set_parallel(true);
          str2.set_parallel(true);
          str.stream_from(r.dig.start_n, r.dig.start_m);
          str2.stream_from(r.dig.start_n, r.dig.start_m);
          for (const auto& s : r.steps)
            for (ErrorMeters* m : {&rec, &str, &rec2, &str2}) m->record(s.axis, s.dir);
          const ErrorMetrics x = rec.finish(r.dig.start_n, r.dig.start_m);
          ASSERT_TRUE(str.streamed() && str2.streamed()) << what;
          const std::pair<ErrorMeters*, const char*> others[] = {
              {&str, ", streamed"}, {&rec2, ", recorded, 2 threads"}, {&str2, ", streamed, 2 threads"}};
          for (const auto& [m, name] : others) {
            const ErrorMetrics y = m->finish(r.dig.start_n, r.dig.start_m);
            const std::string which = what + name;
            EXPECT_EQ(x.area.area_m2, y.area.area_m2) << which;
            EXPECT_EQ(x.deviation_max_m, y.deviation_max_m) << which;
            EXPECT_EQ(x.deviation_at.x, y.deviation_at.x) << which;
            EXPECT_EQ(x.deviation_at.y, y.deviation_at.y) << which;
            EXPECT_EQ(x.f_counts.F1, y.f_counts.F1) << which;
            EXPECT_EQ(x.f_counts.F_sum, y.f_counts.F_sum) << which;
            EXPECT_EQ(x.f_counts.F_dif, y.f_counts.F_dif) << which;
          }
        }
      }
    }
  }
}

// A staircase that, at its end, goes 300 angular steps back and returns: it comes back to sectors measured
// long before, so the streamed meter gives up (streamed() false) rather than miss them; the recorded meter
// measures it.
TEST(AreaStream, AStaircaseThatComesBackIsLeftToTheRecordedMode) {
  const Grid g = coarse_grid(0.0254e-3, 16000);
  auto path = placed(make_limacon(0.0508, 0.0762), 0.0127, 0.0);
  AreaRun r = area_run(*path, g, StepRule::nearest);
  std::vector<Recorded> steps = r.steps;
  Recorded back = steps.front(), fwd = steps.front();
  back.axis = fwd.axis = kAxisAngular;
  back.dir = -1;
  fwd.dir = 1;
  steps.insert(steps.end(), 300, back);
  steps.insert(steps.end(), 300, fwd);
  bool ok = true;
  streamed(r, g, steps, &ok);
  EXPECT_FALSE(ok);
  PolarAreaMeter m;
  m.reset(r.track, g);
  for (const auto& s : steps) m.record(s.axis, s.dir);
  const AreaErrorResult a = m.finish(r.dig.start_n, r.dig.start_m);
  EXPECT_GT(a.area_m2, r.area.area_m2);  // the detour adds area
}

// A staircase that wanders inside the window: here and there it steps back one sector or five and forward again, or
// radially out and in again (no area: each strand is run both ways), or round one cell (back, out, forward, in).
// Those sectors get more than one level strand, most of them after the one-pass queue took the contour's pass: the
// streamed meter measures them with the general sweep, as the recorded one does, with the same area and counts.
TEST(AreaStream, AStaircaseThatWandersInsideTheWindowIsMeasuredAsRecorded) {
  const Grid g = coarse_grid(0.0254e-3, 16000);
  struct Case {
    const char* name;
    ToolPathPtr path;
  };
  const Case cases[] = {{"limacon", placed(make_limacon(0.0508, 0.0762), 0.0127, 0.0)},
                        {"witch", placed(make_witch(0.2159, -0.2032, 0.2032), 0.1546, 1.236)}};
  for (const auto& c : cases) {
    AreaRun r = area_run(*c.path, g, StepRule::nearest);
    size_t total_runs = 0;
    for (const auto& s : r.steps) total_runs += s.axis == kAxisAngular;
    const size_t period = std::max<size_t>(7, total_runs / 60);  // about 60 detours of each kind
    for (bool cells : {false, true}) {
      const std::string what = std::string(c.name) + (cells ? ", round cells" : ", there and back");
      std::vector<Recorded> steps;
      size_t runs = 0, wanders = 0;
      for (const auto& s : r.steps) {
        steps.push_back(s);
        if (s.axis != kAxisAngular) continue;
        ++runs;
        const Recorded back{kAxisAngular, -s.dir, s.t_ns}, fwd = s;
        const Recorded out{kAxisRadial, 1, s.t_ns}, in{kAxisRadial, -1, s.t_ns};
        if (runs % period == 0) {
          const size_t k = runs % (2 * period) == 0 ? 5 : 1;
          steps.insert(steps.end(), k, back);
          if (cells) steps.push_back(out);
          steps.insert(steps.end(), k, fwd);
          if (cells) steps.push_back(in);
          ++wanders;
        } else if (runs % period == period / 2 && !cells) {
          steps.push_back(out);
          steps.push_back(in);
          ++wanders;
        }
      }
      ASSERT_GT(wanders, 50u) << what;
      PolarAreaMeter rec;
      rec.reset(r.track, g);
      for (const auto& s : steps) rec.record(s.axis, s.dir);
      const AreaErrorResult x = rec.finish(r.dig.start_n, r.dig.start_m);
      bool ok = false;
      const AreaErrorResult y = streamed(r, g, steps, &ok);
      ASSERT_TRUE(ok) << what;
      EXPECT_GT(x.general_sectors, wanders / 2) << what;
      if (!cells) {  // strands run both ways enclose nothing
        EXPECT_NEAR(x.area_m2, r.area.area_m2, 1e-9 * r.area.area_m2) << what;
      } else {
        EXPECT_GT(std::abs(x.area_m2 - r.area.area_m2), 1e-3 * r.area.area_m2) << what;
      }
      EXPECT_EQ(std::bit_cast<uint64_t>(y.area_m2), std::bit_cast<uint64_t>(x.area_m2)) << what;
      EXPECT_EQ(y.sectors, x.sectors) << what;
      EXPECT_EQ(y.general_sectors, x.general_sectors) << what;
      EXPECT_EQ(y.run_steps, x.run_steps) << what;
      EXPECT_EQ(y.rise_steps, x.rise_steps) << what;
    }
  }
}

// The witch's tape played backwards, from its end node: every sector's level strand runs against the contour's pass,
// so the streamed meter measures each one from a slot with the general sweep while the steps come. At the end the
// tape is refused, as the recorded meter refuses it: it starts at the path's end, not at its start.
TEST(AreaStream, ATapePlayedBackwardsIsRefusedAsRecorded) {
  const Grid g = coarse_grid(0.0254e-3, 16000);
  auto path = placed(make_witch(0.2159, -0.2032, 0.2032), 0.1546, 1.236);
  AreaRun r = area_run(*path, g, StepRule::nearest);
  std::vector<Recorded> back(r.steps.rbegin(), r.steps.rend());
  for (auto& s : back) s.dir = -s.dir;
  const int64_t n0 = r.dig.end_n, m0 = r.dig.end_m;
  ASSERT_GT(std::abs(m0 - r.dig.start_m), 1000);
  auto message = [&](bool stream) {
    PolarAreaMeter m;
    m.reset(r.track, g);
    if (stream) m.stream_from(n0, m0);
    for (const auto& s : back) m.record(s.axis, s.dir);
    try {
      m.finish(n0, m0);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("not refused");
  };
  const std::string recorded = message(false);
  EXPECT_NE(recorded.find("does not follow this path: its start node"), std::string::npos) << recorded;
  EXPECT_EQ(message(true), recorded);
}

// The lane hands every byte over, in order, across many blocks; a consumer's exception comes back from close();
// a lane dropped without close() stops its thread.
TEST(StepLane, HandsEveryStepOverInOrder) {
  std::vector<uint8_t> got;
  const size_t n = 300001;  // about nine blocks and a part
  {
    StepLane lane([&](const uint8_t* s, size_t k) { got.insert(got.end(), s, s + k); });
    for (size_t i = 0; i < n; ++i) lane.push(static_cast<uint8_t>((i * 7919) % 251));
    lane.close();
  }
  ASSERT_EQ(got.size(), n);
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(got[i], (i * 7919) % 251) << i;

  StepLane bad([](const uint8_t*, size_t) { throw InputError("the consumer refused"); });
  for (size_t i = 0; i < n; ++i) bad.push(1);
  EXPECT_THROW(bad.close(), InputError);

  StepLane dropped([](const uint8_t*, size_t) {});
  for (size_t i = 0; i < 100000; ++i) dropped.push(2);
}  // `dropped` is destroyed without close()

}  // namespace tu_metrics_test_area_stream
