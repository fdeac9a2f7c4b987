// The pulse-rate speed (metrics/pulse_speed.hpp): by hand on synthetic pulses, on the exact Cartesian generator's
// 45-degree line, and measured from a tape against the same measurement in memory.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "cam/curves.hpp"
#include "digitizer/tape.hpp"
#include "metrics/pulse_speed.hpp"
#include "tests/cartesian_rig.hpp"

namespace tu_metrics_test_pulse_speed {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test::exact;
using polarcam::test::RecordingSink;

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

}  // namespace tu_metrics_test_pulse_speed
