// The pulse-rate speed (metrics/pulse_speed.hpp) of the DDA's step streams against the hand calculations of
// docs/cartesian.md: a 45-degree line (hand calculations 1 and 2) and a circle.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "metrics/pulse_speed.hpp"
#include "tests/cartesian_rig.hpp"

namespace tu_metrics_test_dda_speed {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test::dda;

namespace {

PulseSpeedStats speed_of(const std::vector<test::Recorded>& steps, double nominal) {
  PulseSpeedMeter m(kBlu, kBlu);
  for (const auto& s : steps) m.step(s.axis, s.dir, s.t_ns);
  return m.stats(nominal);
}

}  // namespace

// docs/cartesian.md, "Hand calculation 1": a line of 5 BLU on each axis at 50 mm/s, 5 kHz interrupts.
TEST(Dda, FortyFiveDegreeLineHandCalculation) {
  Out o = run({line_seg({0, 0}, {5 * kBlu, 5 * kBlu})}, false, 0.05);
  ASSERT_EQ(o.prog.blocks.size(), 1u);
  EXPECT_EQ(o.prog.blocks[0].path, 7);         // PATH = round(5 sqrt 2) = 7
  EXPECT_EQ(o.prog.blocks[0].feed, 64877u);    // round(65536 * (5000 * 7 / (5 sqrt 2)) / 5000)
  // cycles at interrupts ceil(k 65536 / 64877) = 2..8; pulses at cycles ceil(7 j / 5) = 2, 3, 5, 6, 7
  const int64_t t_ms5[5] = {3, 4, 6, 7, 8};  // interrupts, 0.2 ms each
  ASSERT_EQ(o.rec.steps.size(), 10u);
  for (int j = 0; j < 5; ++j) {
    EXPECT_EQ(o.rec.steps[2 * j].axis, kAxisX);
    EXPECT_EQ(o.rec.steps[2 * j + 1].axis, kAxisY);
    EXPECT_EQ(o.rec.steps[2 * j].t_ns, t_ms5[j] * 200000) << j;
    EXPECT_EQ(o.rec.steps[2 * j + 1].t_ns, t_ms5[j] * 200000) << j;
  }
  EXPECT_EQ(o.res.duration_ns, 8 * 200000);
  // pulse-rate speed: intervals 0.2, 0.4, 0.2, 0.2 ms on both axes -> sqrt(2) BLU / interval
  PulseSpeedStats st = speed_of(o.rec.steps, 0.05);
  const double fast = std::sqrt(2.0) * kBlu / 0.2e-3, slow = fast / 2;  // 70.71 and 35.36 mm/s
  EXPECT_NEAR(st.max_mps, fast, 1e-12);
  EXPECT_NEAR(st.min_mps, slow, 1e-12);
  EXPECT_NEAR(st.mean_mps, 0.6 * fast + 0.4 * slow, 1e-12);  // 56.57 mm/s
  EXPECT_NEAR(st.rms_dev_mps, std::sqrt(0.6 * std::pow(fast - 0.05, 2) + 0.4 * std::pow(slow - 0.05, 2)), 1e-12);
  EXPECT_NEAR(st.rms_dev_mps, 0.01852, 1e-5);  // the figure in the docs
}

// "Hand calculation 2": a long 45-degree line at full feed (one cycle per interrupt).
TEST(Dda, FortyFiveDegreeLineAtFullFeed) {
  const int64_t n = 1000;
  const double L = n * std::sqrt(2.0), hz = 5000.0;
  const int64_t P = std::llround(L);  // 1414
  const double V = hz * kBlu * L / P;  // the speed whose feed word is the accumulator's capacity
  Out o = run({line_seg({0, 0}, {n * kBlu, n * kBlu})}, false, V, hz);
  ASSERT_EQ(o.prog.blocks[0].feed, 65536u);
  ASSERT_EQ(o.rec.steps.size(), static_cast<size_t>(2 * n));
  for (int64_t j = 1; j <= n; ++j) {
    const int64_t cycle = (j * P + n - 1) / n;  // ceil(j P / n): the register starts at zero
    ASSERT_EQ(o.rec.steps[2 * (j - 1)].t_ns, cycle * 200000) << j;
    ASSERT_EQ(o.rec.steps[2 * (j - 1) + 1].t_ns, cycle * 200000) << j;
  }
  EXPECT_EQ(o.res.duration_ns, P * 200000);  // exactly PATH cycles
  // intervals of 1 and 2 cycles: n1 + n2 = n - 1, n1 + 2 n2 = P - ceil(P / n)
  const int64_t n2 = (P - (P + n - 1) / n) - (n - 1), n1 = n - 1 - n2;
  EXPECT_EQ(n1, 586);
  EXPECT_EQ(n2, 413);
  const double fast = std::sqrt(2.0) * kBlu * hz, slow = fast / 2, T = static_cast<double>(n1 + 2 * n2);
  PulseSpeedStats st = speed_of(o.rec.steps, V);
  EXPECT_NEAR(st.max_mps, fast, 1e-12);
  EXPECT_NEAR(st.min_mps, slow, 1e-12);
  EXPECT_NEAR(st.mean_mps, (n1 * fast + 2 * n2 * slow) / T, 1e-12);
  EXPECT_NEAR(st.rms_dev_mps, std::sqrt((n1 * std::pow(fast - V, 2) + 2 * n2 * std::pow(slow - V, 2)) / T), 1e-12);
  // the average speed over the block is the programmed one: L BLU in P cycles of 1 / hz
  EXPECT_NEAR(L * kBlu / (o.res.duration_ns * 1e-9), V, 1e-12);
}

TEST(Dda, CircleStaysNearTheCircleAndItsSpeedIsWithinTheHandBounds) {
  const int64_t R = 400;
  const double V = 5000.0 * kBlu;  // V_i = f_i BLU with f_i = 5000 cycles/s
  Out o = run(circle_segs(static_cast<double>(R), {7, -3}), true, V);
  int64_t n[2] = {o.res.start[0], o.res.start[1]};
  double out = -1e9, in = 1e9;
  for (const auto& s : o.rec.steps) {
    n[s.axis] += s.dir;
    const double r = std::hypot(static_cast<double>(n[0] - 7), static_cast<double>(n[1] + 3));
    out = std::max(out, r - R);
    in = std::min(in, r - R);
  }
  // the staircase lags the circle by less than one step per axis (registers start at zero): measured +1.4/-0.4
  EXPECT_LE(out, 1.5);
  EXPECT_GE(in, -0.5);
  // each axis pulses at intervals of floor or ceil(PATH / integrand) cycles: between V_i / 2 (the fast axis
  // skipping a cycle while the other is nearly still) and sqrt(2) V_i (both on consecutive cycles)
  PulseSpeedStats st = speed_of(o.rec.steps, V);
  EXPECT_NEAR(st.max_mps, std::sqrt(2.0) * V, 1e-12);
  EXPECT_GE(st.min_mps, 0.5 * V - 1e-12);
  EXPECT_LE(st.min_mps, 0.75 * V);
  // the mean over the whole circle: 2 pi R BLU in the measured cycles
  EXPECT_NEAR(2 * kPi * R * kBlu / o.res.duration_s, V, 0.01 * V);
}

}  // namespace tu_metrics_test_dda_speed
