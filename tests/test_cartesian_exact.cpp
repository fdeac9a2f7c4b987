// The exact Cartesian step generator (machine/cartesian/cartesian_exact.hpp) against closed forms: a 45-degree line, a
// circle (every step where the circle meets x or y = (i + 1/2) BLU, 8 R steps, the nodes nearest the path at
// every step time), a ramped speed profile, reversal and the Cartesian track's accuracy.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/path.hpp"
#include "helpers.hpp"
#include "machine/cartesian/cartesian_exact.hpp"
#include "digitizer/tape.hpp"
#include "metrics/pulse_speed.hpp"

using namespace polarcam;
using polarcam::test::RecordingSink;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kBlu = 1e-5;

struct Out {
  RecordingSink rec;
  CartesianResult res;
  CartesianTrack track;
};

Out run(const Curve& c, const SpeedProfile* prof_in, double V = 0.02) {
  Out o;
  o.track = CartesianTrack::build(c);
  SpeedProfilePtr prof = make_constant_speed(V, o.track.length());
  o.res = step_exact(o.track, kBlu, prof_in ? *prof_in : *prof, &o.rec);
  return o;
}

}  // namespace

TEST(CartesianExact, FortyFiveDegreeLineStepsBothAxesTogether) {
  const int n = 200;
  const double V = 0.02;
  auto line = make_line({0, 0}, {n * kBlu, n * kBlu});
  Out o = run(*line, nullptr, V);
  ASSERT_EQ(o.rec.steps.size(), static_cast<size_t>(2 * n));
  for (int k = 1; k <= n; ++k) {
    // both axes cross (k - 1/2) BLU at arc length (k - 1/2) sqrt(2) BLU; x first
    const double t = (k - 0.5) * std::sqrt(2.0) * kBlu / V * 1e9;
    const auto& sx = o.rec.steps[2 * (k - 1)];
    const auto& sy = o.rec.steps[2 * (k - 1) + 1];
    EXPECT_EQ(sx.axis, kAxisX);
    EXPECT_EQ(sy.axis, kAxisY);
    EXPECT_NEAR(static_cast<double>(sx.t_ns), t, 0.5 + 1e-6) << k;
    EXPECT_EQ(sy.t_ns, sx.t_ns) << k;
  }
  EXPECT_NEAR(o.res.duration_s, n * std::sqrt(2.0) * kBlu / V, 1e-15);
  // the pulse-rate speed is the programmed one, to the nanosecond rounding of the times (an interval of
  // sqrt(2) BLU / V = 707107 ns is off by at most 1 ns)
  PulseSpeedMeter m(kBlu, kBlu);
  for (const auto& s : o.rec.steps) m.step(s.axis, s.dir, s.t_ns);
  PulseSpeedStats st = m.stats(V);
  const double tol = V / (std::sqrt(2.0) * kBlu / V * 1e9 - 1.0);
  EXPECT_NEAR(st.min_mps, V, tol);
  EXPECT_NEAR(st.max_mps, V, tol);
  EXPECT_LT(st.rms_dev_mps, tol);
}

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
  auto prof = make_constant_speed(1.0, tr.length());
  EXPECT_THROW(step_exact(tr, 1e-6, *prof, nullptr), InputError);
  // within reach of the node numbers, but 2 * 10^12 steps: refused before any work
  auto metre = make_line({0, 0}, {1.0, 0});
  CartesianTrack tm = CartesianTrack::build(*metre);
  auto pm = make_constant_speed(1.0, tm.length());
  EXPECT_THROW(step_exact(tm, 1e-12, *pm, nullptr), InputError);
}

// ------------------------------------------------------------------------------------ pulse-rate speed

TEST(PulseSpeed, UniformPulsesOnOneAxis) {
  PulseSpeedMeter m(1e-5, 1e-5);
  for (int k = 0; k < 10; ++k) m.step(0, 1, 1000000 * k);  // 1 ms apart: 10 mm/s
  PulseSpeedStats st = m.stats(0.012);
  EXPECT_EQ(st.samples, 9u);
  EXPECT_DOUBLE_EQ(st.min_mps, 0.01);
  EXPECT_DOUBLE_EQ(st.max_mps, 0.01);
  EXPECT_NEAR(st.rms_dev_mps, 0.002, 1e-15);
}

TEST(PulseSpeed, TwoAxesCombineAndTheSlowAxisCountsFromItsFirstInterval) {
  // x every 1 ms, y every 2 ms starting at 1.5 ms: 10 and 5 mm/s; the first x intervals lie before y's first
  // pulse but within one y interval of it, so y counts there too: every sample is hypot(10, 5) mm/s
  PulseSpeedMeter m(1e-5, 1e-5);
  for (int k = 0; k <= 20; ++k) {
    m.step(0, 1, 1000000 * k);
    if (k % 2 == 1 && k < 20) m.step(1, 1, 1000000 * k + 500000);
  }
  PulseSpeedStats st = m.stats(0.0);
  const double v = std::hypot(0.01, 0.005);
  EXPECT_NEAR(st.min_mps, v, 1e-12);
  EXPECT_NEAR(st.max_mps, v, 1e-12);
}

TEST(PulseSpeed, GrazingReversalIsCappedByItsNeighbours) {
  // y rises at 5 mm/s, touches a level and comes straight back (two pulses 10 us apart), then falls at 5 mm/s;
  // x runs at 5 mm/s throughout. Unchecked, the turnaround would read 1 m/s.
  PulseSpeedMeter m(1e-5, 1e-5);
  for (int k = 0; k < 10; ++k) m.step(1, 1, 2000000 * k);
  m.step(1, -1, 2000000 * 9 + 10000);
  for (int k = 1; k < 10; ++k) m.step(1, -1, 2000000 * 9 + 10000 + 2000000 * k);
  for (int k = 0; k < 20; ++k) m.step(0, 1, 2000000 * k);
  PulseSpeedStats st = m.stats(0.0);
  EXPECT_NEAR(st.max_mps, std::hypot(0.005, 0.005), 1e-12);
}

TEST(PulseSpeed, TapeMeasurementEqualsTheInMemoryOne) {
  // a Cartesian tape (the exact generator on a circle) and a polar one (the digitizer on a circle about the pole,
  // where every step is angular and moves the tool r DeltaTheta)
  const std::string path = test::temp_path("speed.tape");
  {
    auto circ = make_circle({3 * kBlu, -2 * kBlu}, 120 * kBlu);
    CartesianTrack tr = CartesianTrack::build(*circ);
    auto prof = make_constant_speed(0.015, tr.length());
    TapeHeader h;
    h.axes = TapeAxes::cartesian;
    h.res[0] = h.res[1] = kBlu;
    PulseSpeedMeter mem(kBlu, kBlu);
    CartesianResult r;
    {
      TapeWriter w(path, h);
      struct Both : StepSink {
        StepSink *a, *b;
        void step(int ax, int d, int64_t t) override {
          a->step(ax, d, t);
          b->step(ax, d, t);
        }
      } both;
      both.a = &w;
      both.b = &mem;
      r = step_exact(tr, kBlu, *prof, &both);
      for (int a = 0; a < 2; ++a) {
        h.start[a] = r.start[a];
        h.end[a] = r.end[a];
      }
      w.finish(h);
    }
    PulseSpeedStats t = measure_tape_speed(path, 0.015), m = mem.stats(0.015);
    EXPECT_EQ(t.samples, m.samples);
    EXPECT_DOUBLE_EQ(t.min_mps, m.min_mps);
    EXPECT_DOUBLE_EQ(t.max_mps, m.max_mps);
    EXPECT_DOUBLE_EQ(t.rms_dev_mps, m.rms_dev_mps);
    EXPECT_GT(t.samples, 900u);
  }
  {
    const double R = 0.1, V = 0.02;
    Grid g = test::thesis_grid();
    auto run = test::run_digitizer(*make_tool_path(make_circle({0, 0}, R), Placement{}, ToolSpec{}, TravelSpec{}), g,
                                   StepRule::nearest, V);
    TapeHeader h;
    h.res[0] = g.dr;
    h.res[1] = g.dtheta;
    h.start[0] = h.end[0] = run.result.start_n;
    h.start[1] = run.result.start_m;
    h.end[1] = run.result.end_m;
    {
      TapeWriter w(path, h);
      for (const auto& s : run.steps) w.step(s.axis, s.dir, s.t_ns);
      w.finish(h);
    }
    // the node's radius n DeltaR = 3937 x 0.0254 mm is 0.2 um short of R: the speed reads V n DeltaR / R
    const double v = V * static_cast<double>(run.result.start_n) * g.dr / R;
    PulseSpeedStats st = measure_tape_speed(path, V);
    const double tol = v * 1.0 / (R * g.dtheta / V * 1e9);  // 1 ns in an interval of 1963 us
    EXPECT_NEAR(st.min_mps, v, tol);
    EXPECT_NEAR(st.max_mps, v, tol);
  }
  std::remove(path.c_str());
}
