// The DDA interpolator (machine/cartesian/dda.hpp) against hand calculations and an independent transcription of the
// listing's registers: the linear DDA's pulse pattern and timing, the feed accumulator, the two-integrator
// circular DDA on full circles (8 R / BLU steps). The hand calculations with pulse-rate speeds (docs/cartesian.md)
// are in tests/metrics/test_dda_speed.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "cam/error.hpp"
#include "cam/path.hpp"
#include "machine/cartesian/dda.hpp"
#include "tests/cartesian_rig.hpp"

namespace tu_machine_cartesian_test_dda {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test::dda;

TEST(Dda, LinePulsesFollowTheRegisterOverflows) {
  // every direction: after k cycles an axis has floor(k |delta| / PATH) pulses; full feed, so cycle = interrupt
  const int64_t ends[][2] = {{37, 11}, {-23, 40}, {-31, -31}, {50, -3}, {0, -17}, {29, 0}, {1, 1}};
  for (const auto& e : ends) {
    SCOPED_TRACE(std::to_string(e[0]) + "," + std::to_string(e[1]));
    const double L = std::hypot(static_cast<double>(e[0]), static_cast<double>(e[1]));
    const int64_t P = std::llround(L);
    Out o = run({line_seg({0, 0}, {e[0] * kBlu, e[1] * kBlu})}, false, 5000.0 * kBlu * L / P);
    ASSERT_EQ(o.prog.blocks[0].feed, 65536u);
    int64_t count[2] = {0, 0}, expect_t[2] = {0, 0};
    for (const auto& s : o.rec.steps) {
      const int a = s.axis;
      const int64_t d = std::llabs(e[a]);
      ++count[a];
      expect_t[a] = ((count[a] * P + d - 1) / d) * 200000;
      EXPECT_EQ(s.t_ns, expect_t[a]);
      EXPECT_EQ(s.dir, e[a] > 0 ? 1 : -1);
    }
    EXPECT_EQ(count[0], std::llabs(e[0]));
    EXPECT_EQ(count[1], std::llabs(e[1]));
    EXPECT_EQ(o.res.end[0], e[0]);
    EXPECT_EQ(o.res.end[1], e[1]);
  }
}

TEST(Dda, FeedAccumulatorTimesEveryCycleAndRestartsEachBlock) {
  // two horizontal blocks; x pulses every cycle; cycle k of a block at ceil(k capacity / F) interrupts after the
  // block's start (the accumulator is cleared at each block, as the listing's INIT does)
  const double V = 0.0123, hz = 5000.0;
  std::vector<PathSegment> segs = {line_seg({0, 0}, {40 * kBlu, 0}), line_seg({40 * kBlu, 0}, {40 * kBlu, 25 * kBlu})};
  Out o = run(segs, false, V, hz);
  const uint64_t F = static_cast<uint64_t>(std::nearbyint(65536.0 * (V / kBlu) / hz));
  ASSERT_EQ(o.prog.blocks[0].feed, F);
  ASSERT_EQ(o.rec.steps.size(), 65u);
  uint64_t J0 = 0;
  for (size_t i = 0; i < 65; ++i) {
    const uint64_t k = i < 40 ? i + 1 : i - 39;
    if (i == 40) J0 = (40 * 65536 + F - 1) / F;
    const uint64_t J = J0 + (k * 65536 + F - 1) / F;
    EXPECT_EQ(o.rec.steps[i].t_ns, static_cast<int64_t>(J * 200000)) << i;
    EXPECT_EQ(o.rec.steps[i].axis, i < 40 ? kAxisX : kAxisY);
  }
  EXPECT_EQ(o.stats.cycles, 65u);
}

namespace {

// The circular DDA transcribed from the listing's CIRC2/CIRC3 for a circle about the origin, one quadrant at a
// time: the first register adds the integrand Y and pulses the axis moving away from the centre line (whose
// magnitude Y2 then grows by one); the second adds Y2 and pulses the other axis (whose magnitude Y shrinks).
// Returns (axis, dir, cycle) for a counter-clockwise or clockwise circle of integer radius R from (R, 0).
struct RefStep {
  int axis, dir;
  int64_t cycle;
};
std::vector<RefStep> reference_circle(int64_t R, bool ccw) {
  // per quadrant travelled: the growing axis and the directions (growing, shrinking)
  struct Q {
    int grow;
    int dgrow, dshrink;
  };
  const Q qs_ccw[4] = {{1, +1, -1}, {0, -1, -1}, {1, -1, +1}, {0, +1, +1}};  // I, II, III, IV
  const Q qs_cw[4] = {{1, -1, -1}, {0, -1, +1}, {1, +1, +1}, {0, +1, -1}};   // IV, III, II, I
  std::vector<RefStep> out;
  int64_t cycle = 0;
  for (int q = 0; q < 4; ++q) {
    const Q& d = ccw ? qs_ccw[q] : qs_cw[q];
    int64_t Y = R, Y2 = 0, C1 = R, C2 = R, Ra = 0, Rb = 0;  // Y = |shrinking|, Y2 = |growing|
    while (C1 > 0 || C2 > 0) {
      ++cycle;
      if (C1 > 0 && (Ra += Y) >= R) {
        Ra -= R;
        --C1;
        ++Y2;
        out.push_back({d.grow, d.dgrow, cycle});
      }
      if (C2 > 0 && (Rb += Y2) >= R) {
        Rb -= R;
        --C2;
        --Y;
        out.push_back({1 - d.grow, d.dshrink, cycle});
      }
    }
  }
  return out;
}

}  // namespace

TEST(Dda, FullCircleTakesEightRStepsAndMatchesTheListing) {
  for (int64_t R : {5, 37, 250}) {
    for (bool ccw : {true, false}) {
      SCOPED_TRACE("R " + std::to_string(R) + (ccw ? " ccw" : " cw"));
      const double V = 5000.0 * kBlu;  // full feed: PATH = R, one cycle per interrupt
      Out o = run(circle_segs(static_cast<double>(R), {0, 0}, ccw), true, V);
      EXPECT_EQ(o.res.steps(), static_cast<uint64_t>(8 * R));
      for (int a = 0; a < 2; ++a) {
        EXPECT_EQ(o.res.axis[a].plus, static_cast<uint64_t>(2 * R));
        EXPECT_EQ(o.res.axis[a].minus, static_cast<uint64_t>(2 * R));
      }
      EXPECT_TRUE(o.res.returns_to_start);
      EXPECT_EQ(o.stats.cleanup_steps, 0u);
      ASSERT_EQ(o.prog.arc_blocks, 4u);
      for (const auto& b : o.prog.blocks) {
        EXPECT_EQ(b.path, R);
        EXPECT_EQ(b.feed, 65536u);
      }
      auto ref = reference_circle(R, ccw);
      ASSERT_EQ(ref.size(), o.rec.steps.size());
      for (size_t i = 0; i < ref.size(); ++i) {
        ASSERT_EQ(o.rec.steps[i].axis, ref[i].axis) << i;
        ASSERT_EQ(o.rec.steps[i].dir, ref[i].dir) << i;
        ASSERT_EQ(o.rec.steps[i].t_ns, ref[i].cycle * 200000) << i;
      }
      // about 2 pi R cycles: one BLU of arc per cycle, so the average speed is the programmed one
      EXPECT_NEAR(static_cast<double>(o.stats.cycles) / (2 * kPi * R), 1.0, 0.02);
    }
  }
}

TEST(Dda, CircleOffTheGridIsWithinTheDocumentedEndPointRounding) {
  // a circle from angle 0: its quarter arcs end on the rounded extreme points, so N = 2 (D_x + D_y) with
  // D_x = round(c_x + R) - round(c_x - R) in {floor(2R), ceil(2R)}: |N - 8 R| < 4, and N = 8 R when 2 R is whole
  const double cases[][3] = {{5905.51, 3937.01, 1968.504}, {0.3, -0.45, 100.7}, {12.5, 7.49, 33.33},
                             {-3.2, 8.8, 57.5},           {0.49, 0.51, 20.5},   {-7.7, 2.2, 40.0}};
  for (const auto& c : cases) {
    SCOPED_TRACE(std::to_string(c[2]));
    Out o = run(circle_segs(c[2], {c[0], c[1]}), true, 0.02);
    const double N = static_cast<double>(o.res.steps());
    EXPECT_LT(std::abs(N - 8 * c[2]), 4.0);
    if (std::fmod(2 * c[2], 1.0) == 0.0) {
      EXPECT_EQ(N, 8 * c[2]);
    }
    EXPECT_EQ(o.res.steps() % 2, 0u);
    EXPECT_TRUE(o.res.returns_to_start);
  }
}

TEST(Dda, ArcsOfEveryQuadrantAndDirectionEndOnTheirEndPoints) {
  // quarter and partial arcs, both directions, starting anywhere: every block ends on its end node
  for (int k = 0; k < 16; ++k) {
    const double a0 = 0.37 * k, sweep = (k % 2 ? -1.0 : 1.0) * (0.3 + 0.1 * k);
    const Vec2 c{123.4 * kBlu, -56.7 * kBlu};
    const double R = 300.0 * kBlu;
    PathSegment s = make_arc_segment(c + Vec2{R * std::cos(a0), R * std::sin(a0)}, c, sweep);
    Out o = run({s}, false, 0.01);
    const int64_t ex = std::llround(s.to.x / kBlu), ey = std::llround(s.to.y / kBlu);
    EXPECT_EQ(o.res.end[0], ex) << k;
    EXPECT_EQ(o.res.end[1], ey) << k;
    // steps within a quadrant are monotone on each axis: the counts are the node distances per quadrant
    EXPECT_GE(o.res.steps(), static_cast<uint64_t>(std::llabs(ex - o.res.start[0]) + std::llabs(ey - o.res.start[1])));
  }
}

TEST(Dda, RefusesAFeedTheInterruptsCannotCarry) {
  // 0.1 m/s at 0.01 mm needs 10^4 cycles per second
  EXPECT_THROW(run({line_seg({0, 0}, {1e-3, 0})}, false, 0.1, 5000.0), InputError);
  EXPECT_NO_THROW(run({line_seg({0, 0}, {1e-3, 0})}, false, 0.1, 10000.0));
  EXPECT_THROW(run({line_seg({0, 0}, {1e-3, 0})}, false, 1e-9, 5000.0), InputError);  // the feed word rounds to 0
  EXPECT_THROW(make_dda_program({}, false, kBlu, 0.01, DdaOptions{}), InputError);
  // a metre on a 1e-12 m grid: 10^12 steps, refused before any work
  EXPECT_THROW(make_dda_program({line_seg({0, 0}, {1.0, 0})}, false, 1e-12, 1e-9, DdaOptions{}), InputError);
}

}  // namespace tu_machine_cartesian_test_dda
