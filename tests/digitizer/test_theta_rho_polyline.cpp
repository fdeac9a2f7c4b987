// Theta-rho polylines (cam/theta_rho_path.hpp) stepped from their vertices (digitizer/theta_rho.hpp): every step
// of both motors against an independent walk of the segments written here. On each segment theta and rho are
// linear, so a motor's steps fall where its coordinate (rho + c theta, or theta) crosses a level halfway between
// nodes, at a fraction of the segment found by one division; the time of each is the ball's arc length to that
// point (composite Gauss-Legendre in long double on sqrt(drho^2 + max(rho, r_floor)^2 dtheta^2), in panels that
// break where rho crosses r_floor) over the speed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "cam/error.hpp"
#include "cam/theta_rho_path.hpp"
#include "digitizer/theta_rho.hpp"
#include "tests/helpers.hpp"

namespace tu_digitizer_test_theta_rho_polyline {  // the test files of a program compile together (unity build)

using namespace polarcam;
using polarcam::test::RecordingSink;

namespace {

using ld = long double;

// Arc length (timing length) of the segment a -> b from fraction 0 to phi.
ld seg_len(const ThetaRho& a, const ThetaRho& b, ld phi, ld r_floor) {
  static const ld x[4] = {0.1834346424956498049394761L, 0.5255324099163289858177390L, 0.7966664774136267395915539L,
                          0.9602898564975362316835609L};
  static const ld w[4] = {0.3626837833783619829651504L, 0.3137066458778872873379622L, 0.2223810344533744705443560L,
                          0.1012285362903762591525314L};
  const ld dth = (ld)b.theta - a.theta, drho = (ld)b.rho - a.rho;
  auto g = [&](ld f) {
    const ld rho = std::max((ld)a.rho + drho * f, r_floor);
    return std::sqrt(drho * drho + rho * rho * dth * dth);
  };
  auto integrate = [&](ld from, ld to) {
    const int panels = 64;
    ld sum = 0;
    for (int p = 0; p < panels; ++p) {
      const ld lo = from + (to - from) * p / panels, hi = from + (to - from) * (p + 1) / panels;
      const ld m = 0.5L * (lo + hi), h = 0.5L * (hi - lo);
      for (int k = 0; k < 4; ++k) sum += h * w[k] * (g(m - h * x[k]) + g(m + h * x[k]));
    }
    return sum;
  };
  const ld kink = drho != 0 ? (r_floor - (ld)a.rho) / drho : -1;  // rho = r_floor there
  if (kink > 0 && kink < phi) return integrate(0, kink) + integrate(kink, phi);
  return integrate(0, phi);
}

struct RefStep {
  int axis, dir;
  ld s;
  ld dq_ds;  // |d(motor coordinate) / d(arc length)| at the step: how well its place is defined
  ld q_scale;  // size of the numbers the motor coordinate is computed from (its rounding is 8 eps of it)
};

// The independent walk: every level crossing of both motors, in order of arc length (radial first on a tie).
std::vector<RefStep> reference(const std::vector<ThetaRho>& v, const Grid& g, double c, double r_floor,
                               int64_t& n0, int64_t& m0) {
  const ld res[2] = {g.dr, g.dtheta};
  auto q = [&](const ThetaRho& p, int axis) -> ld { return axis == 0 ? (ld)p.rho + (ld)c * p.theta : (ld)p.theta; };
  n0 = static_cast<int64_t>(std::floor(q(v[0], 0) / res[0] + 0.5L));
  m0 = static_cast<int64_t>(std::floor(q(v[0], 1) / res[1] + 0.5L));
  std::vector<RefStep> out;
  ld s0 = 0;
  for (size_t k = 0; k + 1 < v.size(); ++k) {
    std::vector<std::pair<ld, RefStep>> seg;
    for (int axis = 0; axis < 2; ++axis) {
      const ld fa = q(v[k], axis) / res[axis], fb = q(v[k + 1], axis) / res[axis];
      if (fb > fa)
        for (ld lv = std::floor(fa + 0.5L) + 0.5L; lv <= fb; lv += 1) seg.push_back({(lv - fa) / (fb - fa), {axis, +1, 0, 0, 0}});
      else if (fb < fa)
        for (ld lv = std::floor(fa + 0.5L) - 0.5L; lv > fb; lv -= 1) seg.push_back({(lv - fa) / (fb - fa), {axis, -1, 0, 0, 0}});
    }
    std::stable_sort(seg.begin(), seg.end(), [](const auto& x, const auto& y) {
      return x.first < y.first || (x.first == y.first && x.second.axis < y.second.axis);
    });
    for (auto& [phi, st] : seg) {
      st.s = s0 + seg_len(v[k], v[k + 1], phi, r_floor);
      const ld dth = (ld)v[k + 1].theta - v[k].theta, drho = (ld)v[k + 1].rho - v[k].rho;
      const ld rho = (ld)v[k].rho + drho * phi, th = (ld)v[k].theta + dth * phi;
      const ld rho_t = std::max(rho, (ld)r_floor);
      const ld ds = std::sqrt(drho * drho + rho_t * rho_t * dth * dth);
      st.dq_ds = std::abs(st.axis == 0 ? drho + (ld)c * dth : dth) / ds;
      st.q_scale = st.axis == 0 ? std::abs(rho) + std::abs((ld)c * th) : std::abs(th);
      out.push_back(st);
    }
    s0 += seg_len(v[k], v[k + 1], 1.0L, r_floor);
  }
  return out;
}

// The steps of the pattern from the held track (ThetaRhoTrack) or, `streamed`, from the streamed one
// (PolylineTrack, which makes each piece as it is walked).
void expect_matches_reference(const std::vector<ThetaRho>& v, const Grid& g, double c, double r_floor, double speed,
                              bool streamed = false) {
  auto curve = make_theta_rho_path(v, "test pattern");
  const auto& path = *as_theta_rho_path(*curve);
  RecordingSink sink;
  DigitizeResult res;
  if (streamed) {
    const PolylineTrack tr(path, c, r_floor);
    auto prof = make_constant_speed(speed, tr.length());
    res = digitize(tr, g, StepRule::nearest, *prof, &sink);
  } else {
    ThetaRhoTrack tr = ThetaRhoTrack::build(path, c, r_floor);
    auto prof = make_constant_speed(speed, tr.length());
    res = digitize(tr, g, StepRule::nearest, *prof, &sink);
  }
  int64_t n0, m0;
  std::vector<RefStep> ref = reference(v, g, c, r_floor, n0, m0);
  EXPECT_EQ(res.start_n, n0);
  EXPECT_EQ(res.start_m, m0);
  ASSERT_EQ(sink.steps.size(), ref.size());
  int64_t n = n0, m = m0;
  for (size_t i = 0; i < ref.size(); ++i) {
    ASSERT_EQ(sink.steps[i].axis, ref[i].axis) << "step " << i;
    ASSERT_EQ(sink.steps[i].dir, ref[i].dir) << "step " << i;
    const ld t_ref = ref[i].s / speed * 1e9L;
    // 1 ns, and more only where the motor barely moves along the path, so that the rounding of its coordinate
    // in double (a few units in the last place) moves the crossing further than 1 ns
    const ld tol = 1.0L + 8 * 2.2e-16L * ref[i].q_scale / ref[i].dq_ds / speed * 1e9L;
    ASSERT_LE(std::abs((ld)sink.steps[i].t_ns - t_ref), tol) << "step " << i << " dq/ds " << (double)ref[i].dq_ds;
    (ref[i].axis == 0 ? n : m) += ref[i].dir;
  }
  EXPECT_EQ(res.end_n, n);
  EXPECT_EQ(res.end_m, m);
}

Grid coarse_grid() {
  Grid g;
  g.dr = 0.2e-3;
  g.steps_per_rev = 1600;
  g.dtheta = dtheta_from_steps(g.steps_per_rev);
  return g;
}

// A pattern of our own: cumulative theta far past +-100 rad, through the centre, back and forth (`up` points
// going up, then `down` coming back).
std::vector<ThetaRho> wild_pattern(int up = 25, int down = 15) {
  const double R = 0.2;
  std::vector<ThetaRho> v;
  double th = 0.3;
  for (int i = 0; i < up + down; ++i) {
    const double rho = R * (i % 7 == 3 ? 0.0 : 0.5 + 0.45 * std::sin(1.7 * i));
    v.push_back({th, rho});
    th += (i < up ? 6.1 : -13.5) + 0.37 * std::cos(2.3 * i);  // out past +140 rad, then back below -40 rad
  }
  return v;
}

// The pattern of the two longest comparisons with the reference walk. Under the sanitizers, whose run checks the
// memory and the undefined behaviour of the same calls, a shorter one: 8 points up and 4 back (through the centre
// twice, out to 49 rad and back below 0; about 100 rad of travel instead of 355).
std::vector<ThetaRho> long_or_short_pattern() {
#ifdef POLARCAM_SANITIZED
  return wild_pattern(8, 4);
#else
  return wild_pattern();
#endif
}

}  // namespace

TEST(ThetaRhoPolyline, StepsMatchAnIndependentWalkOfTheSegments) {
  const auto v = wild_pattern();
  double lo = 1e9, hi = -1e9;
  for (const auto& p : v) lo = std::min(lo, p.theta), hi = std::max(hi, p.theta);
  ASSERT_GT(hi, 100.0);  // the pattern does what the test says it does
  ASSERT_LT(lo, -30.0);
  expect_matches_reference(v, coarse_grid(), 0.0, 0.0, 0.04);
}

TEST(ThetaRhoPolyline, CoupledArmAndTimingRadiusMatchTheWalk) {
  auto v = long_or_short_pattern();
  // a turn of the arm at the centre (no ball motion): timed by the timing radius
  v.insert(v.begin() + 4, {v[3].theta + 2.5, 0.0});
  ASSERT_EQ(v[3].rho, 0.0);
  const double c = 0.2e-3 * 3200 / (2 * std::numbers::pi) * 0.01;  // 0.032 radial steps per angular step
  expect_matches_reference(v, coarse_grid(), c, 0.004, 0.04);
  expect_matches_reference(v, coarse_grid(), -c, 0.004, 0.03);
}

TEST(ThetaRhoPolyline, AnArmTurnAtTheCentreNeedsATimingRadius) {
  std::vector<ThetaRho> v = {{0.0, 0.1}, {0.0, 0.0}, {3.0, 0.0}, {3.0, 0.1}};
  auto curve = make_theta_rho_path(v, "turn");
  try {
    (void)ThetaRhoTrack::build(*as_theta_rho_path(*curve), 0.0, 0.0);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "segment 2 (points 2-3)");
    EXPECT_NE(std::string(e.what()).find("max_angular_speed"), std::string::npos);
  }
  // with a timing radius the turn takes the time of an arc of that radius
  ThetaRhoTrack tr = ThetaRhoTrack::build(*as_theta_rho_path(*curve), 0.0, 0.01);
  EXPECT_NEAR(tr.length(), 0.1 + 3.0 * 0.01 + 0.1, 1e-15);
}

// Sand-table patterns often start and end at the centre: the ball is back where it started whatever theta, but the
// arm is not unless it turned by whole turns. Such a pattern is open for the motors (the tape ends on another
// angular node; it was refused as an internal error, "a closed path did not return to its start node"); one that
// comes back after a whole turn is closed, with a winding of one.
TEST(ThetaRhoPolyline, APatternFromTheCentreBackToItIsClosedOnlyAfterWholeTurns) {
  const double c = 0.2e-3 * 3200 / (2 * std::numbers::pi) * 0.01;
  const std::vector<ThetaRho> open = {{0.0, 0.0}, {1.0, 0.1}, {2.0, 0.0}};
  const std::vector<ThetaRho> turn = {{0.0, 0.0}, {std::numbers::pi, 0.1}, {2 * std::numbers::pi, 0.0}};
  auto open_curve = make_theta_rho_path(open, "out and back");
  auto turn_curve = make_theta_rho_path(turn, "a turn");
  ASSERT_TRUE(open_curve->closed());  // in the plane: back at the centre
  for (double cc : {0.0, c}) {
    EXPECT_FALSE(ThetaRhoTrack::build(*as_theta_rho_path(*open_curve), cc, 0.004).closed());
    EXPECT_FALSE(PolylineTrack(*as_theta_rho_path(*open_curve), cc, 0.004).closed());
    const ThetaRhoTrack whole = ThetaRhoTrack::build(*as_theta_rho_path(*turn_curve), cc, 0.004);
    EXPECT_TRUE(whole.closed());
    EXPECT_EQ(whole.winding(), 1);
    EXPECT_TRUE(PolylineTrack(*as_theta_rho_path(*turn_curve), cc, 0.004).closed());
    // every step against the independent walk, the end node included
    expect_matches_reference(open, coarse_grid(), cc, 0.004, 0.04);
    expect_matches_reference(open, coarse_grid(), cc, 0.004, 0.04, true);
    expect_matches_reference(turn, coarse_grid(), cc, 0.004, 0.04);
  }
}

TEST(ThetaRhoPolyline, PolarTrackOfAPolylineIsRAndTheta) {
  // through the pole and out the other side: r goes to 0 and back, theta continues linearly (the arm's angle)
  std::vector<ThetaRho> v = {{0.5, 0.08}, {0.5, 0.0}, {0.5 + std::numbers::pi, 0.05}};
  auto curve = make_theta_rho_path(v, "across");
  PolarTrack tr = polyline_polar_track(*as_theta_rho_path(*curve), 0.0);
  EXPECT_DOUBLE_EQ(tr.r_min().value, 0.0);
  EXPECT_DOUBLE_EQ(tr.r_max().value, 0.08);
  EXPECT_DOUBLE_EQ(tr.theta_max().value, 0.5 + std::numbers::pi);
  // second segment: the Archimedean spiral r = 0.05 phi / pi from the pole, length by its closed form
  const double b = 0.05 / std::numbers::pi, phi = std::numbers::pi;
  const double spiral = 0.5 * b * (phi * std::sqrt(1 + phi * phi) + std::asinh(phi));
  EXPECT_NEAR(tr.length(), 0.08 + spiral, 1e-15);
}

// The streamed track (PolylineTrack) makes each piece from its two vertices as the walk reaches it, so that a
// pattern of any length digitizes in the memory of one piece: its steps against the independent walk.
TEST(ThetaRhoPolyline, StreamedTrackMatchesTheWalk) {
  expect_matches_reference(long_or_short_pattern(), coarse_grid(), 0.0, 0.0, 0.04, true);
  auto v = long_or_short_pattern();
  ASSERT_EQ(v[3].rho, 0.0);
  v.insert(v.begin() + 4, {v[3].theta + 2.5, 0.0});  // a turn of the arm at the centre: timed by r_floor
  const double c = 0.2e-3 * 3200 / (2 * std::numbers::pi) * 0.01;
  expect_matches_reference(v, coarse_grid(), c, 0.004, 0.04, true);
  expect_matches_reference(v, coarse_grid(), -c, 0.004, 0.03, true);
}

// Tapes and summaries must not change when a pattern is streamed: the same steps at the same nanoseconds, the
// same summary, as the held track's, on the thesis rule of a closed pattern too (its start node comes from a lap).
TEST(ThetaRhoPolyline, StreamedTrackGivesTheHeldTracksTapeExactly) {
  auto v = wild_pattern();
  v.insert(v.begin() + 4, {v[3].theta + 2.5, 0.0});
  std::vector<ThetaRho> closed = {{0.2, 0.05}, {1.0, 0.12}, {2.5, 0.0}, {4.0, 0.0}, {5.0, 0.09}};
  closed.push_back({0.2 + 4 * std::numbers::pi, 0.05});  // back at the start, two turns on
  const double c = 0.2e-3 * 3200 / (2 * std::numbers::pi) * 0.01;
  for (const auto& [pattern, closes] : {std::pair{v, false}, std::pair{closed, true}})
    for (double cc : {0.0, c, -c})
      for (StepRule rule : {StepRule::nearest, StepRule::thesis}) {
        SCOPED_TRACE(std::string(to_string(rule)) + " c " + std::to_string(cc));
        auto curve = make_theta_rho_path(pattern, "p");
        const auto& path = *as_theta_rho_path(*curve);
        ASSERT_EQ(path.closed(), closes);
        const ThetaRhoTrack held = ThetaRhoTrack::build(path, cc, 0.004);
        const PolylineTrack streamed(path, cc, 0.004);
        ASSERT_EQ(streamed.size(), held.pieces().size());
        EXPECT_EQ(streamed.length(), held.length());
        EXPECT_EQ(streamed.winding(), held.winding());
        auto prof = make_constant_speed(0.03, held.length());
        RecordingSink a, b;
        const DigitizeResult ra = digitize(held, coarse_grid(), rule, *prof, &a);
        const DigitizeResult rb = digitize(streamed, coarse_grid(), rule, *prof, &b);
        ASSERT_GT(a.steps.size(), 1000u);
        ASSERT_EQ(a.steps.size(), b.steps.size());
        for (size_t i = 0; i < a.steps.size(); ++i) {
          ASSERT_EQ(a.steps[i].axis, b.steps[i].axis) << "step " << i;
          ASSERT_EQ(a.steps[i].dir, b.steps[i].dir) << "step " << i;
          ASSERT_EQ(a.steps[i].t_ns, b.steps[i].t_ns) << "step " << i;
        }
        EXPECT_EQ(ra.start_n, rb.start_n);
        EXPECT_EQ(ra.start_m, rb.start_m);
        EXPECT_EQ(ra.end_n, rb.end_n);
        EXPECT_EQ(ra.end_m, rb.end_m);
        EXPECT_EQ(ra.duration_ns, rb.duration_ns);
        EXPECT_EQ(ra.radial.max_rate_hz, rb.radial.max_rate_hz);
        EXPECT_EQ(ra.angular.max_rate_hz, rb.angular.max_rate_hz);
        EXPECT_EQ(ra.radial.min_interval_ns, rb.radial.min_interval_ns);
        EXPECT_EQ(ra.angular.min_interval_ns, rb.angular.min_interval_ns);
        EXPECT_EQ(ra.returns_to_start, rb.returns_to_start);
        // the polar track's ranges (rho and theta) as polyline_polar_track has them
        const PolarTrack polar = polyline_polar_track(path, 0.004);
        EXPECT_EQ(streamed.r_min().value, polar.r_min().value);
        EXPECT_EQ(streamed.r_max().value, polar.r_max().value);
        EXPECT_EQ(streamed.q_min(1).value, polar.theta_min().value);
        EXPECT_EQ(streamed.q_max(1).value, polar.theta_max().value);
      }
}

// A sink that follows the nodes learns where the tape starts from StepSink::begin, once, before the first step.
TEST(ThetaRhoPolyline, TheSinkIsToldTheStartNodeBeforeTheFirstStep) {
  struct BeginSink : StepSink {
    int begins = 0;
    size_t steps_before = 0, steps = 0;
    int64_t n = 0, m = 0;
    void begin(int64_t a, int64_t b) override {
      ++begins;
      steps_before = steps;
      n = a, m = b;
    }
    void step(int, int, int64_t) override { ++steps; }
  };
  const auto v = wild_pattern();
  auto curve = make_theta_rho_path(v, "p");
  const PolylineTrack tr(*as_theta_rho_path(*curve), 0.0, 0.0);
  auto prof = make_constant_speed(0.04, tr.length());
  BeginSink sink;
  const DigitizeResult r = digitize(tr, coarse_grid(), StepRule::nearest, *prof, &sink);
  EXPECT_EQ(sink.begins, 1);
  EXPECT_EQ(sink.steps_before, 0u);
  EXPECT_GT(sink.steps, 0u);
  // the nearest nodes of the first vertex, worked out here
  EXPECT_EQ(sink.n, static_cast<int64_t>(std::floor(v[0].rho / coarse_grid().dr + 0.5)));
  EXPECT_EQ(sink.m, static_cast<int64_t>(std::floor(v[0].theta / coarse_grid().dtheta + 0.5)));
  EXPECT_EQ(sink.n, r.start_n);
  EXPECT_EQ(sink.m, r.start_m);
}

// A pattern that leaves the work area is refused with the same message, naming the same place, streamed or held.
TEST(ThetaRhoPolyline, StreamedTrackRefusesWhatTheHeldTrackRefuses) {
  const auto v = wild_pattern();
  auto curve = make_theta_rho_path(v, "p");
  const auto& path = *as_theta_rho_path(*curve);
  Grid g = coarse_grid();
  g.r_max = 0.15;  // the pattern reaches 0.19 m
  auto message = [&](auto&& track) {
    auto prof = make_constant_speed(0.04, track.length());
    try {
      (void)digitize(track, g, StepRule::nearest, *prof, nullptr);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string held = message(ThetaRhoTrack::build(path, 0.0, 0.0));
  EXPECT_NE(held.find("r_max"), std::string::npos) << held;
  EXPECT_EQ(message(PolylineTrack(path, 0.0, 0.0)), held);
}

}  // namespace tu_digitizer_test_theta_rho_polyline
