// The theta-rho coupled arm (digitizer/theta_rho.hpp): with no coupling it is the polar machine step for step;
// with a coupling every step of both motors is checked against a slow independent computation on the curve itself
// (long double bisection of q = r + c theta and of theta along the circle's own angle, whose arc length is exact).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/toolpath.hpp"
#include "digitizer/theta_rho.hpp"
#include "tests/helpers.hpp"

namespace tu_digitizer_test_theta_rho {  // the test files of a program compile together (unity build)

using namespace polarcam;
using polarcam::test::RecordingSink;
using polarcam::test::thesis_grid;

namespace {

struct Taped {
  DigitizeResult res;
  std::vector<test::Recorded> steps;
};

template <class Track>
Taped tape_of(const Track& tr, const Grid& g, StepRule rule, double v) {
  auto prof = make_constant_speed(v, tr.length());
  RecordingSink sink;
  Taped t;
  t.res = digitize(tr, g, rule, *prof, &sink);
  t.steps = std::move(sink.steps);
  return t;
}

void expect_same_tape(const Taped& a, const Taped& b) {
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (size_t i = 0; i < a.steps.size(); ++i) {
    ASSERT_EQ(a.steps[i].axis, b.steps[i].axis) << i;
    ASSERT_EQ(a.steps[i].dir, b.steps[i].dir) << i;
    ASSERT_EQ(a.steps[i].t_ns, b.steps[i].t_ns) << i;
  }
  EXPECT_EQ(a.res.start_n, b.res.start_n);
  EXPECT_EQ(a.res.start_m, b.res.start_m);
  EXPECT_EQ(a.res.end_n, b.res.end_n);
  EXPECT_EQ(a.res.end_m, b.res.end_m);
  EXPECT_EQ(a.res.returns_to_start, b.res.returns_to_start);
  EXPECT_EQ(a.res.theta_shift, b.res.theta_shift);
  EXPECT_EQ(a.res.radial.max_rate_hz, b.res.radial.max_rate_hz);
  EXPECT_EQ(a.res.angular.max_rate_hz, b.res.angular.max_rate_hz);
}

}  // namespace

TEST(ThetaRho, WithoutCouplingItIsThePolarMachineStepForStep) {
  std::vector<ToolPathPtr> paths = {
      make_tool_path(make_limacon(0.0508, 0.0762), Placement{0.0, 0.0}, ToolSpec{}, TravelSpec{}),
      make_tool_path(make_limacon(0.0508, 0.0762), Placement{0.15, 0.3}, ToolSpec{}, TravelSpec{}),
      make_tool_path(make_circle({0.03, 0.01}, 0.02), Placement{0.0, 0.0}, ToolSpec{}, TravelSpec{})};
  for (const auto& p : paths)
    for (StepRule rule : {StepRule::nearest, StepRule::thesis}) {
      const Grid g = thesis_grid();
      const PolarTrack polar = PolarTrack::build(*p);
      const ThetaRhoTrack arm = ThetaRhoTrack::build(*p, 0.0);
      ASSERT_EQ(polar.pieces().size(), arm.pieces().size());
      expect_same_tape(tape_of(polar, g, rule, 0.02), tape_of(arm, g, rule, 0.02));
    }
}

namespace {

// The circle p(phi) = (d + a cos phi, a sin phi), phi in [0, 2 pi], in long double: theta unwrapped from its
// start angle 0 and the motor coordinates f0 = (r + c theta) / dq, f1 = theta / dtheta in steps.
struct Circle {
  long double d, a, c, dq, dth;
  void motors(long double phi, long double& th_ref, long double f[2]) const {
    const long double x = d + a * std::cos(phi), y = a * std::sin(phi);
    long double th = std::atan2(y, x);
    const long double two_pi = 2.0L * std::numbers::pi_v<long double>;
    th += two_pi * std::nearbyint((th_ref - th) / two_pi);
    th_ref = th;
    f[0] = (std::hypot(x, y) + c * th) / dq;
    f[1] = th / dth;
  }
};

struct RefStep {
  long double phi;
  int axis, dir;
};

// Every crossing of a level k + 1/2 of either motor (the nearest rule), in order of phi: the circle is sampled
// densely and each level between neighbouring samples is bisected on the curve to long double precision.
std::vector<RefStep> reference_steps(const Circle& cv, int samples) {
  std::vector<RefStep> out;
  const long double two_pi = 2.0L * std::numbers::pi_v<long double>;
  long double th_ref = 0.0L, f_prev[2];
  cv.motors(0.0L, th_ref, f_prev);
  long double phi_prev = 0.0L;
  for (int i = 1; i <= samples; ++i) {
    const long double phi = two_pi * i / samples;
    const long double th_prev = th_ref;
    long double f[2];
    cv.motors(phi, th_ref, f);
    for (int a = 0; a < 2; ++a) {
      const int dir = f[a] > f_prev[a] ? 1 : -1;
      long double lo_l = std::min(f[a], f_prev[a]), hi_l = std::max(f[a], f_prev[a]);
      for (long double L = std::floor(lo_l - 0.5L) + 0.5L; L <= hi_l; L += 1.0L) {
        if (!(L > lo_l && L <= hi_l)) continue;
        long double lo = phi_prev, hi = phi;
        for (int it = 0; it < 80; ++it) {
          const long double mid = 0.5L * (lo + hi);
          long double ref = th_prev, fm[2];
          cv.motors(mid, ref, fm);
          if ((fm[a] < L) == (dir > 0))
            lo = mid;
          else
            hi = mid;
        }
        out.push_back({0.5L * (lo + hi), a, dir});
      }
      f_prev[a] = f[a];
    }
    phi_prev = phi;
  }
  std::stable_sort(out.begin(), out.end(), [](const RefStep& x, const RefStep& y) { return x.phi < y.phi; });
  return out;
}

void check_against_reference(double d, double a, double c) {
  Grid g;
  g.dr = 20e-6;
  g.steps_per_rev = 3200;
  g.dtheta = dtheta_from_steps(g.steps_per_rev);
  const double V = 0.02;
  auto circle = make_circle({d, 0.0}, a);
  const ThetaRhoTrack tr = ThetaRhoTrack::build(*circle, c);
  const Taped tp = tape_of(tr, g, StepRule::nearest, V);
  ASSERT_EQ(tp.res.theta_shift, 0.0);  // the circle starts at theta = 0: no whole-turn shift

  const Circle cv{d, a, c, g.dr, g.dtheta};
  const std::vector<RefStep> ref = reference_steps(cv, 400000);
  ASSERT_EQ(tp.steps.size(), ref.size());
  long double worst = 0.0L;
  for (size_t i = 0; i < ref.size(); ++i) {
    // the arc length along the circle is a phi exactly; the constant-speed profile makes t = s / V
    const long double t_ns = static_cast<long double>(a) * ref[i].phi / V * 1e9L;
    const long double diff = std::abs(t_ns - static_cast<long double>(tp.steps[i].t_ns));
    // two steps of different motors closer than a nanosecond may come in either order
    if (tp.steps[i].axis != ref[i].axis && diff <= 1.0L) continue;
    ASSERT_EQ(tp.steps[i].axis, ref[i].axis) << "step " << i;
    ASSERT_EQ(tp.steps[i].dir, ref[i].dir) << "step " << i;
    worst = std::max(worst, diff);
  }
  EXPECT_LE(worst, 1.0L);
}

}  // namespace

TEST(ThetaRho, CoupledArmAroundThePoleMatchesTheCurveStepForStep) {
  check_against_reference(0.02, 0.05, 0.004);  // the path winds once about the pole: q drifts 2 pi c
}

TEST(ThetaRho, NegativeCouplingOffThePoleMatchesTheCurveStepForStep) {
  check_against_reference(0.08, 0.03, -0.003);  // theta reverses twice; q = r - 0.003 theta
}

TEST(ThetaRho, WindingWithCouplingDoesNotCloseTheRadialMotor) {
  Grid g;
  g.dr = 20e-6;
  g.steps_per_rev = 3200;
  g.dtheta = dtheta_from_steps(g.steps_per_rev);
  const double c = 0.004, R = 0.05;
  auto circle = make_circle({0.0, 0.0}, R);  // about the pole: r constant, q = R + c theta
  const ThetaRhoTrack tr = ThetaRhoTrack::build(*circle, c);
  EXPECT_EQ(tr.winding(), 1);
  const Taped tp = tape_of(tr, g, StepRule::nearest, 0.02);
  // the radial motor alone follows c theta: floor((R + 2 pi c) / dq + 1/2) - floor(R / dq + 1/2) steps out
  const auto n0 = static_cast<int64_t>(std::floor(R / g.dr + 0.5));
  const auto n1 = static_cast<int64_t>(std::floor((R + 2 * std::numbers::pi * c) / g.dr + 0.5));
  EXPECT_EQ(tp.res.start_n, n0);
  EXPECT_EQ(tp.res.end_n, n1);
  EXPECT_EQ(tp.res.radial.minus, 0u);
  EXPECT_EQ(tp.res.end_m - tp.res.start_m, 3200);
  EXPECT_FALSE(tp.res.returns_to_start);
}

TEST(ThetaRho, TheWorkAreaBoundsTheBallNotTheGearedRadialMotor) {
  Grid g = thesis_grid();
  g.r_min = 0.04;
  g.r_max = 0.06;
  auto circle = make_circle({0.0, 0.0}, 0.05);
  // r stays at 0.05 m; with c = -0.003 m/rad the radial motor itself goes down to 0.05 - 0.003 * 2 pi < 0.04,
  // which is no limit: it is geared to the arm
  const ThetaRhoTrack tr = ThetaRhoTrack::build(*circle, -0.003);
  auto prof = make_constant_speed(0.02, tr.length());
  EXPECT_NO_THROW(digitize(tr, g, StepRule::nearest, *prof, nullptr));
  // the ball's radius is bounded: a circle of radius 49.5 mm 2 mm off the pole reaches r = 51.5 mm
  auto off = make_circle({0.002, 0.0}, 0.0495);
  const ThetaRhoTrack tr2 = ThetaRhoTrack::build(*off, -0.003);
  auto prof2 = make_constant_speed(0.02, tr2.length());
  g.r_max = 0.0514;
  try {
    digitize(tr2, g, StepRule::nearest, *prof2, nullptr);
    FAIL() << "expected the path to leave the work area";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("r reaches 51.5 mm"), std::string::npos) << e.what();
  }
  g.r_max = 0.0516;
  EXPECT_NO_THROW(digitize(tr2, g, StepRule::nearest, *prof2, nullptr));
}

}  // namespace tu_digitizer_test_theta_rho
