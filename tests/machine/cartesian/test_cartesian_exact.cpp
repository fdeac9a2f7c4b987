// The exact Cartesian step generator (machine/cartesian/cartesian_exact.hpp) against closed forms: a 45-degree line, a
// circle (every step where the circle meets x or y = (i + 1/2) BLU, 8 R steps, the nodes nearest the path at
// every step time), a ramped speed profile, reversal and the Cartesian track's accuracy.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/path.hpp"
#include "tests/cartesian_rig.hpp"
#include "machine/cartesian/cartesian_exact.hpp"

namespace tu_machine_cartesian_test_cartesian_exact {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test::exact;
using polarcam::test::RecordingSink;

TEST(CartesianExact, CircleStepsWhereItMeetsTheHalfLevels) {
  // circle of radius R = 120 BLU about (3, -2) BLU from angle 0, counter-clockwise
  const double R = 120, V = 0.015, cx = 3, cy = -2;
  auto circ = make_circle({cx * kBlu, cy * kBlu}, R * kBlu);
  Out o = run(*circ, nullptr, V);
  EXPECT_EQ(o.res.steps(), static_cast<uint64_t>(8 * R));
  EXPECT_TRUE(o.res.returns_to_start);
  EXPECT_EQ(o.res.start[0], 123);
  EXPECT_EQ(o.res.start[1], -2);
  int64_t n[2] = {o.res.start[0], o.res.start[1]};
  double worst_level = 0, worst_node = 0;
  for (const auto& s : o.rec.steps) {
    const int64_t before = n[s.axis];
    n[s.axis] += s.dir;
    // the path point at the step's time (arc length V t, angle V t / R)
    const double phi = V * (static_cast<double>(s.t_ns) * 1e-9) / (R * kBlu);
    const double p[2] = {cx + R * std::cos(phi), cy + R * std::sin(phi)};
    const double level = static_cast<double>(before) + 0.5 * s.dir;
    // the time is rounded to 1 ns: the coordinate is within V * 0.5 ns of the level
    worst_level = std::max(worst_level, std::abs(p[s.axis] - level));
    for (int a = 0; a < 2; ++a) worst_node = std::max(worst_node, std::abs(p[a] - static_cast<double>(n[a])));
  }
  const double ns_in_blu = V * 0.5e-9 / kBlu;  // 7.5e-7 BLU
  EXPECT_LE(worst_level, ns_in_blu + 1e-9);
  EXPECT_LE(worst_node, 0.5 + ns_in_blu + 1e-9);  // the node nearest the path point, on both axes
  EXPECT_NEAR(o.res.duration_s, 2 * kPi * R * kBlu / V, 1e-14);
}

TEST(CartesianExact, RampedProfileTimesStepsByTheProfile) {
  // a horizontal line from rest at a = 0.5 m/s^2 to 20 mm/s: step k at s = (k - 1/2) BLU, t = sqrt(2 s / a) on the
  // ramp
  const double V = 0.02, a = 0.5;
  auto line = make_line({0, 0}, {300 * kBlu, 0});
  CartesianTrack tr = CartesianTrack::build(*line);
  SpeedProfilePtr prof = make_trapezoid_speed(V, a, tr.length());
  RecordingSink rec;
  CartesianResult r = step_exact(tr, kBlu, *prof, &rec);
  ASSERT_EQ(rec.steps.size(), 300u);
  const double s_ramp = V * V / (2 * a);  // 0.4 mm = 40 BLU
  for (int k = 1; k <= 40; ++k) {
    const double s = (k - 0.5) * kBlu;
    ASSERT_LT(s, s_ramp);
    EXPECT_NEAR(static_cast<double>(rec.steps[k - 1].t_ns), std::sqrt(2 * s / a) * 1e9, 0.5 + 1e-3) << k;
  }
  EXPECT_NEAR(r.duration_s, 2 * V / a + (300 * kBlu - 2 * s_ramp) / V, 1e-12);
}

TEST(CartesianExact, ReversedCircleIsTheMirrorImage) {
  auto circ = make_circle({0, 0}, 57.3 * kBlu);
  auto fwd = make_tool_path(circ, Placement{}, ToolSpec{}, TravelSpec{});
  TravelSpec rev;
  rev.reverse = true;
  auto bwd = make_tool_path(circ, Placement{}, ToolSpec{}, rev);
  Out a = run(*fwd, nullptr), b = run(*bwd, nullptr);
  ASSERT_EQ(a.rec.steps.size(), b.rec.steps.size());
  // reversal mirrors the circle in y: x steps identical, y steps opposite
  for (size_t i = 0; i < a.rec.steps.size(); ++i) {
    EXPECT_EQ(a.rec.steps[i].axis, b.rec.steps[i].axis) << i;
    EXPECT_EQ(a.rec.steps[i].dir, a.rec.steps[i].axis == kAxisX ? b.rec.steps[i].dir : -b.rec.steps[i].dir) << i;
    EXPECT_NEAR(a.rec.steps[i].t_ns, b.rec.steps[i].t_ns, 1) << i;
  }
}

TEST(CartesianExact, TrackIsAccurateToRounding) {
  auto lim = make_limacon(0.0508, 0.0762);
  CartesianTrack tr = CartesianTrack::build(*lim);
  double worst = 0;
  for (size_t i = 0; i < tr.pieces().size(); ++i) {
    const TrackPiece& p = tr.pieces()[i];
    for (int j = 0; j <= 10; ++j) {
      const double t = -1.0 + 0.2 * j;
      const Vec2 q = lim->eval(0.5 * (p.ua + p.ub) + 0.5 * (p.ub - p.ua) * t, 0).p;
      worst = std::max({worst, std::abs(tr.x(i, t) - q.x), std::abs(tr.y(i, t) - q.y)});
    }
  }
  EXPECT_LT(worst, 1e-15);
  // perimeter of the limacon b + a cos(theta) by a plain trapezoid rule on |P'| (smooth and periodic: spectral)
  const int M = 4000;
  double L = 0;
  for (int k = 0; k < M; ++k) L += norm(lim->eval(2 * kPi * k / M, 1).d1);
  L *= 2 * kPi / M;
  EXPECT_NEAR(tr.length(), L, 1e-13);
}

TEST(CartesianExact, PathTooLargeForTheResolutionIsAnError) {
  auto line = make_line({0, 0}, {1e12, 0});
  CartesianTrack tr = CartesianTrack::build(*line);
  // at 1 m/s the 1e12 m line would take 1e21 ns, beyond what a tape times: the speed profile refuses it
  EXPECT_THROW(make_constant_speed(1.0, tr.length()), InputError);
  auto prof = make_constant_speed(1e6, tr.length());  // 1e15 ns: timed, but 1e18 steps beyond the node numbers
  EXPECT_THROW(step_exact(tr, 1e-6, *prof, nullptr), InputError);
  // within reach of the node numbers, but 2 * 10^12 steps: refused before any work
  auto metre = make_line({0, 0}, {1.0, 0});
  CartesianTrack tm = CartesianTrack::build(*metre);
  auto pm = make_constant_speed(1.0, tm.length());
  EXPECT_THROW(step_exact(tm, 1e-12, *pm, nullptr), InputError);
}

}  // namespace tu_machine_cartesian_test_cartesian_exact
