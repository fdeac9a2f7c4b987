// Analytic cases of the digitizer: a circle about the pole, a radial line, closure, reversal, start shift,
// simultaneous steps, speed profiles, the thesis rule's hysteresis and the work-area checks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/path.hpp"
#include "cam/segments.hpp"
#include "cam/spline.hpp"
#include "tests/helpers.hpp"

namespace tu_digitizer_test_digitizer_analytic {  // the test files of a program compile together (unity build)

using namespace polarcam;
using polarcam::test::RecordingSink;
using polarcam::test::run_digitizer;
using polarcam::test::thesis_grid;

namespace {
constexpr double kPi = std::numbers::pi;
ToolPathPtr placed(CurvePtr c, double C = 0, double beta = 0, TravelSpec tr = {}) {
  return make_tool_path(std::move(c), Placement{C, beta}, ToolSpec{}, tr);
}
}  // namespace

TEST(DigitizerAnalytic, CircleAboutThePoleTakesOnlyEqualAngularSteps) {
  const double R = 0.1, V = 0.02;
  Grid g = thesis_grid();
  auto run = run_digitizer(*placed(make_circle({0, 0}, R)), g, StepRule::nearest, V);
  EXPECT_EQ(run.result.radial.steps(), 0u);
  ASSERT_EQ(run.result.angular.steps(), 16000u);
  EXPECT_EQ(run.result.angular.minus, 0u);
  // step k (1-based) where the arm crosses theta = (k - 1/2) dtheta: t = R (k - 1/2) dtheta / V
  for (size_t k = 1; k <= run.steps.size(); ++k) {
    double exact = R * (static_cast<double>(k) - 0.5) * g.dtheta / V * 1e9;
    ASSERT_NEAR(static_cast<double>(run.steps[k - 1].t_ns), exact, 0.5 + 1e-6) << "step " << k;
  }
  EXPECT_TRUE(run.result.returns_to_start);
  EXPECT_EQ(run.result.end_m, run.result.start_m + 16000);
  EXPECT_NEAR(run.result.duration_s, 2 * kPi * R / V, 1e-12);
}

TEST(DigitizerAnalytic, NoDriftOverTenMillionSteps) {
  // 10^7 angular steps in one turn of a circle about the pole: every time is exact to the rounding of 1 ns
  const double R = 0.2, V = 0.05;
  Grid g;
  g.dr = 1e-6;
  g.steps_per_rev = 10'000'000;
  g.dtheta = dtheta_from_steps(g.steps_per_rev);
  PolarTrack tr = PolarTrack::build(*placed(make_circle({0, 0}, R)));
  auto prof = make_constant_speed(V, tr.length());
  struct Check : StepSink {
    double R, V, dth;
    int64_t k = 0;
    double worst = 0;
    void step(int axis, int, int64_t t_ns) override {
      ++k;
      EXPECT_EQ(axis, kAxisAngular);
      double exact = R * (static_cast<double>(k) - 0.5) * dth / V * 1e9;
      worst = std::max(worst, std::abs(static_cast<double>(t_ns) - exact));
    }
  } check;
  check.R = R;
  check.V = V;
  check.dth = g.dtheta;
  DigitizeResult r = digitize(tr, g, StepRule::nearest, *prof, &check);
  EXPECT_EQ(check.k, 10'000'000);
  EXPECT_EQ(r.angular.steps(), 10'000'000u);
  EXPECT_LE(check.worst, 0.5 + 1e-3);
}

TEST(DigitizerAnalytic, RadialLineTakesOnlyRadialSteps) {
  const double r0 = 0.1, r1 = 0.2, V = 0.01;
  Grid g = thesis_grid();
  auto run = run_digitizer(*placed(make_line({r0, 0.0}, {r1, 0.0})), g, StepRule::nearest, V);
  EXPECT_EQ(run.result.angular.steps(), 0u);
  int64_t n0 = static_cast<int64_t>(std::floor(r0 / g.dr + 0.5)), n1 = static_cast<int64_t>(std::floor(r1 / g.dr + 0.5));
  ASSERT_EQ(run.result.radial.plus, static_cast<uint64_t>(n1 - n0));
  EXPECT_EQ(run.result.start_n, n0);
  EXPECT_EQ(run.result.end_n, n1);
  for (size_t i = 0; i < run.steps.size(); ++i) {
    double level = (static_cast<double>(n0 + static_cast<int64_t>(i)) + 0.5) * g.dr;
    ASSERT_NEAR(static_cast<double>(run.steps[i].t_ns), (level - r0) / V * 1e9, 0.5 + 1e-6);
  }
}

TEST(DigitizerAnalytic, ReversedTravelMirrorsTheTape) {
  auto fwd = run_digitizer(*placed(make_witch(0.2159, -0.2032, 0.2032), 0.1546, 1.236), thesis_grid(),
                           StepRule::nearest, 0.0152);
  TravelSpec rev;
  rev.reverse = true;
  auto bwd = run_digitizer(*placed(make_witch(0.2159, -0.2032, 0.2032), 0.1546, 1.236, rev), thesis_grid(),
                           StepRule::nearest, 0.0152);
  ASSERT_EQ(fwd.steps.size(), bwd.steps.size());
  EXPECT_EQ(fwd.result.start_n, bwd.result.end_n);
  EXPECT_EQ(fwd.result.start_m, bwd.result.end_m);
  const size_t n = fwd.steps.size();
  const int64_t T = std::llround(fwd.result.duration_s * 1e9);
  for (size_t i = 0; i < n; ++i) {
    const auto& a = fwd.steps[i];
    const auto& b = bwd.steps[n - 1 - i];
    ASSERT_EQ(a.axis, b.axis);
    ASSERT_EQ(a.dir, -b.dir);
    ASSERT_NEAR(static_cast<double>(b.t_ns), static_cast<double>(T - a.t_ns), 1.0);
  }
}

TEST(DigitizerAnalytic, StartParameterRotatesAClosedTape) {
  // a circle off the pole: starting elsewhere gives the same steps, cyclically shifted
  auto base = run_digitizer(*placed(make_circle({0, 0}, 0.05), 0.2, 4.0), thesis_grid(), StepRule::nearest, 0.01);
  TravelSpec t;
  t.start_parameter = 2.0;
  auto shifted = run_digitizer(*placed(make_circle({0, 0}, 0.05), 0.2, 4.0, t), thesis_grid(), StepRule::nearest, 0.01);
  ASSERT_EQ(base.steps.size(), shifted.steps.size());
  EXPECT_TRUE(shifted.result.returns_to_start);
  // find the shift: the first shifted step equals some base step in axis/direction sequence
  const size_t n = base.steps.size();
  size_t match = n;
  for (size_t k = 0; k < n && match == n; ++k) {
    bool ok = true;
    for (size_t i = 0; i < n && ok; ++i)
      ok = base.steps[(k + i) % n].axis == shifted.steps[i].axis && base.steps[(k + i) % n].dir == shifted.steps[i].dir;
    if (ok) match = k;
  }
  EXPECT_LT(match, n);
}

TEST(DigitizerAnalytic, ClosedContoursReturnToTheirStartNode) {
  std::vector<Vec2> pts;
  for (int i = 0; i < 50; ++i) {
    double t = 2 * kPi * i / 50, r = 0.05 + 0.01 * std::cos(3 * t);
    pts.push_back({r * std::cos(t), r * std::sin(t)});
  }
  for (auto c : {make_limacon(0.0508, 0.0762), make_circle({0.01, 0.02}, 0.03), make_spline(pts, true, "")}) {
    for (StepRule rule : {StepRule::nearest, StepRule::thesis}) {
      for (double C : {0.0127, 0.2}) {
        auto run = run_digitizer(*placed(c, C, 0.7), thesis_grid(), rule, 0.01);
        EXPECT_TRUE(run.result.returns_to_start) << c->name() << " C=" << C << " rule " << to_string(rule);
        EXPECT_EQ(run.result.end_n, run.result.start_n);
        EXPECT_EQ(run.result.end_m, run.result.start_m + run.result.winding * 16000);
      }
    }
  }
}

TEST(DigitizerAnalytic, SimultaneousStepsHaveZeroInterval) {
  // a line through the grid point where the circle r = (n + 1/2) dR meets the ray theta = (m + 1/2) dtheta
  Grid g = thesis_grid();
  double r = (4000 + 0.5) * g.dr, th = (1000 + 0.5) * g.dtheta;
  Vec2 p{r * std::cos(th), r * std::sin(th)}, dir{0.6, -0.8};
  auto run = run_digitizer(*placed(make_line(p - dir * 1e-4, p + dir * 1e-4)), g, StepRule::nearest, 0.01);
  bool found = false;
  for (size_t i = 1; i < run.steps.size(); ++i)
    if (run.steps[i].axis != run.steps[i - 1].axis && run.steps[i].t_ns == run.steps[i - 1].t_ns) found = true;
  EXPECT_TRUE(found);
}

TEST(DigitizerAnalytic, ThesisRuleStepsAFullResolutionFromTheNode) {
  // radial line: the thesis rule truncates the start and steps when r reaches the next whole resolution
  Grid g = thesis_grid();
  const double r0 = (5000 + 0.3) * g.dr, r1 = (5010 + 0.7) * g.dr, V = 0.01;
  auto run = run_digitizer(*placed(make_line({r0, 0}, {r1, 0})), g, StepRule::thesis, V);
  EXPECT_EQ(run.result.start_n, 5000);
  EXPECT_EQ(run.result.end_n, 5010);
  ASSERT_EQ(run.steps.size(), 10u);
  for (size_t i = 0; i < 10; ++i)
    EXPECT_NEAR(static_cast<double>(run.steps[i].t_ns), ((5001.0 + static_cast<double>(i)) * g.dr - r0) / V * 1e9, 0.5 + 1e-6);
  // back and forth within one resolution: no step at all (hysteresis), whereas nearest steps twice
  const double ra = (6000 + 0.2) * g.dr, rb = (6000 + 0.8) * g.dr;
  std::vector<PathSegment> segs(2);
  segs[0].from = {ra, 0};
  segs[0].to = {rb, 0};
  segs[1].from = {rb, 0};
  segs[1].to = {ra, 0};
  auto zig = make_path(segs, false);
  EXPECT_EQ(run_digitizer(*placed(zig), g, StepRule::thesis, V).steps.size(), 0u);
  EXPECT_EQ(run_digitizer(*placed(zig), g, StepRule::nearest, V).steps.size(), 2u);
}

TEST(DigitizerAnalytic, TrapezoidProfileTimesFollowTheRamp) {
  const double R = 0.1, V = 0.02, a = 0.01;
  Grid g = thesis_grid();
  PolarTrack tr = PolarTrack::build(*placed(make_circle({0, 0}, R)));
  auto prof = make_trapezoid_speed(V, a, tr.length());
  RecordingSink sink;
  DigitizeResult r = digitize(tr, g, StepRule::nearest, *prof, &sink);
  const double L = 2 * kPi * R, sa = V * V / (2 * a), T = 2 * V / a + (L - 2 * sa) / V;
  EXPECT_NEAR(r.duration_s, T, 1e-9);
  for (size_t k = 1; k <= sink.steps.size(); k += 997) {
    double s = R * (static_cast<double>(k) - 0.5) * g.dtheta;
    double t = s <= sa ? std::sqrt(2 * s / a) : (s <= L - sa ? V / a + (s - sa) / V : T - std::sqrt(2 * (L - s) / a));
    ASSERT_NEAR(static_cast<double>(sink.steps[k - 1].t_ns), t * 1e9, 1.0);
  }
}

TEST(DigitizerAnalytic, TableProfileIntegratesOneOverV) {
  // V rising linearly from V0 to V1 over the path: t(s) = L/(V1-V0) ln(V(s)/V0)
  const double R = 0.1, V0 = 0.01, V1 = 0.03;
  PolarTrack tr = PolarTrack::build(*placed(make_circle({0, 0}, R)));
  const double L = tr.length();
  auto prof = make_table_speed({{0.0, V0}, {L, V1}}, L);
  EXPECT_NEAR(prof->total_time(), L / (V1 - V0) * std::log(V1 / V0), 1e-12);
  EXPECT_NEAR(prof->time_at(0.3 * L), L / (V1 - V0) * std::log((V0 + 0.3 * (V1 - V0)) / V0), 1e-12);
}

TEST(DigitizerAnalytic, WorkAreaViolationsNameWhere) {
  Grid g = thesis_grid();
  g.r_min = 0.0762;
  g.r_max = 0.3302;
  g.theta_min = 0.0;
  g.theta_max = 2.8;
  auto inside = PolarTrack::build(*placed(make_circle({0, 0}, 0.05), 0.2032, 3 * kPi / 2));
  EXPECT_NO_THROW(place_on_grid(inside, g));
  auto far = PolarTrack::build(*placed(make_circle({0, 0}, 0.05), 0.3, 3 * kPi / 2));
  try {
    place_on_grid(far, g);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("r_max"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("path parameter"), std::string::npos) << e.what();
  }
  auto around = PolarTrack::build(*placed(make_circle({0, 0}, 0.2), 0.01, 0));
  EXPECT_THROW(place_on_grid(around, g), InputError);  // a full turn does not fit 0 .. 2.8 rad
}

TEST(DigitizerAnalytic, PoleOnThePathIsAnError) {
  EXPECT_THROW(PolarTrack::build(*placed(make_circle({0, 0}, 0.05), 0.05, 0.3)), InputError);
  EXPECT_THROW(PolarTrack::build(*placed(make_line({-0.1, 0}, {0.1, 0}))), InputError);
}

TEST(DigitizerAnalytic, PassingCloseToThePoleStaysExact) {
  // a straight line passing 0.1 mm from the pole: theta sweeps almost pi in a few millimetres
  Grid g = thesis_grid();
  const double d = 1e-4, V = 0.01;
  auto run = run_digitizer(*placed(make_line({-0.05, d}, {0.05, d})), g, StepRule::nearest, V);
  // angular steps: theta goes from atan2(d, -0.05) down to atan2(d, 0.05)
  double th0 = std::atan2(d, -0.05), th1 = std::atan2(d, 0.05);
  int64_t m0 = static_cast<int64_t>(std::floor(th0 / g.dtheta + 0.5)), m1 = static_cast<int64_t>(std::floor(th1 / g.dtheta + 0.5));
  EXPECT_EQ(run.result.angular.minus, static_cast<uint64_t>(m0 - m1));
  EXPECT_EQ(run.result.angular.plus, 0u);
  // the angular step at theta = (m + 1/2) dtheta is where x = d / tan(theta): t = (x + 0.05) / V
  size_t k = 0;
  for (const auto& s : run.steps) {
    if (s.axis != kAxisAngular) continue;
    double th = (static_cast<double>(m0 - static_cast<int64_t>(k)) - 0.5) * g.dtheta;
    double x = d / std::tan(th);
    ASSERT_NEAR(static_cast<double>(s.t_ns), (x + 0.05) / V * 1e9, 1.0) << "angular step " << k;
    ++k;
  }
}

TEST(DigitizerAnalytic, SegmentCurveStepsAsTheSameArcLengthPath) {
  // a slot (two lines, two half circles of radius 1 cm) as a path parametrised by arc length and as a curve of
  // segments with one parameter unit each, whose speed |P'| jumps at every joint: the same steps at the same times
  const double r = 0.01;
  auto path = make_path({PathSegment{PathSegment::Kind::line, {0.04, -r}, {0.08, -r}, {}, 0},
                         make_arc_segment({0.08, -r}, {0.08, 0}, kPi),
                         PathSegment{PathSegment::Kind::line, {0.08, r}, {0.04, r}, {}, 0},
                         make_arc_segment({0.04, r}, {0.04, 0}, kPi)},
                        true);
  auto segs = make_segment_curve({line_segment({0.04, -r}, {0.08, -r}), arc_segment({0.08, 0}, {r, 0}, {0, r}, -kPi / 2, kPi / 2),
                                  line_segment({0.08, r}, {0.04, r}), arc_segment({0.04, 0}, {r, 0}, {0, r}, kPi / 2, 3 * kPi / 2)},
                                 true, "slot");
  const double L = 2 * 0.04 + 2 * kPi * r;
  auto a = run_digitizer(*placed(path), thesis_grid(), StepRule::nearest, 0.0152);
  auto b = run_digitizer(*placed(segs), thesis_grid(), StepRule::nearest, 0.0152);
  EXPECT_NEAR(b.track.length(), L, 1e-15);
  EXPECT_NEAR(b.result.path_length_m, L, 1e-15);
  EXPECT_TRUE(b.result.returns_to_start);
  ASSERT_EQ(a.steps.size(), b.steps.size());
  ASSERT_GT(a.steps.size(), 1000u);
  int64_t worst = 0;
  for (size_t i = 0; i < a.steps.size(); ++i) {
    ASSERT_EQ(a.steps[i].axis, b.steps[i].axis) << i;
    ASSERT_EQ(a.steps[i].dir, b.steps[i].dir) << i;
    worst = std::max(worst, std::abs(a.steps[i].t_ns - b.steps[i].t_ns));
  }
  EXPECT_LE(worst, 1);  // nanosecond rounding of the same time
}

TEST(DigitizerAnalytic, DurationsBeyondTheTapesTicksNameTheLowestSpeed) {
  // a tape times steps in 64-bit nanoseconds, bounded at 2^62 ns: a 0.1 m path fits down to 0.1 m / 2^62 ns
  const double L = 0.1, v_min = L / (std::ldexp(1.0, 62) * 1e-9);  // 2.168...e-11 m/s
  for (double v : {1e-300, v_min * 0.99}) {
    try {
      make_constant_speed(v, L);
      FAIL() << v;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("lowest speed that fits is 2.17e-11 m/s"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(make_constant_speed(2.17e-11, L));  // the speed named fits
  EXPECT_THROW(make_table_speed({{0.0, 1e-300}, {L, 2e-300}}, L), InputError);
  EXPECT_THROW(make_trapezoid_speed(1e-300, 1.0, L), InputError);
}

TEST(DigitizerAnalytic, StepRatesBeyondOneTickAndGridsBeyondTheTapeAreRefused) {
  // 1e308 m/s on a circle of radius 0.1 m: the angular rate V / (R dtheta) is infinite in double precision, and
  // every step would fall on one tick
  Grid g = thesis_grid();
  try {
    run_digitizer(*placed(make_circle({0, 0}, 0.1)), g, StepRule::nearest, 1e308);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1 ns tick"), std::string::npos) << e.what();
  }
  // 1e9 steps per second is the bound: V = 1e9 * R dtheta / 2 is below it
  EXPECT_NO_THROW(run_digitizer(*placed(make_circle({0, 0}, 0.1)), g, StepRule::nearest, 0.5e9 * 0.1 * g.dtheta));
  Grid fine = g;
  fine.dr = 1e-13;
  EXPECT_THROW(fine.validate(), InputError);
  EXPECT_THROW(dtheta_from_steps((int64_t{1} << 40) + 1), InputError);
  EXPECT_NO_THROW(dtheta_from_steps(int64_t{1} << 40));
  EXPECT_EQ(steps_per_rev_from_dtheta(1e-300), 0);  // far beyond 2^40 steps: no whole number is claimed
  Grid far = g;
  far.r_max.reset();
  far.home_r = 1e12;  // 1e12 m / 25.4 um = 3.9e16 steps from node 0, beyond 2^50
  EXPECT_THROW(far.validate(), InputError);
  // a radial step longer than the work area's span from r_min to r_max: no step fits in it
  Grid coarse = g;
  coarse.r_min = 0.010;
  coarse.r_max = 0.050;
  coarse.dr = 0.040;
  EXPECT_NO_THROW(coarse.validate());
  coarse.dr = 0.0401;
  try {
    coarse.validate();
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("40.1 mm is coarser than the work area's radial span (40 mm"), std::string::npos)
        << e.what();
  }
}

}  // namespace tu_digitizer_test_digitizer_analytic
