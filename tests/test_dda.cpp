// The DDA interpolator (machine/cartesian/dda.hpp) against hand calculations and an independent transcription of the
// listing's registers: the linear DDA's pulse pattern and timing, the feed accumulator, the two-integrator
// circular DDA on full circles (8 R / BLU steps), and the pulse-rate speed along a 45-degree line and a circle
// (the hand calculations of docs/cartesian.md).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "cam/error.hpp"
#include "cam/path.hpp"
#include "helpers.hpp"
#include "machine/cartesian/dda.hpp"
#include "metrics/pulse_speed.hpp"

using namespace polarcam;
using polarcam::test::RecordingSink;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kBlu = 1e-5;  // 0.01 mm

PathSegment line_seg(Vec2 a, Vec2 b) {
  PathSegment s;
  s.from = a;
  s.to = b;
  return s;
}

// A full counter-clockwise circle of radius R BLU about the node c, starting at angle 0, as four quarter arcs.
std::vector<PathSegment> circle_segs(double R, Vec2 c = {0, 0}, bool ccw = true) {
  std::vector<PathSegment> segs;
  for (int q = 0; q < 4; ++q) {
    const double a = (ccw ? 1 : -1) * q * kPi / 2;
    segs.push_back(make_arc_segment({(c.x + R * std::cos(a)) * kBlu, (c.y + R * std::sin(a)) * kBlu}, c * kBlu,
                                    ccw ? kPi / 2 : -kPi / 2));
  }
  segs.back().to = segs.front().from;
  return segs;
}

struct Out {
  RecordingSink rec;
  CartesianResult res;
  DdaStats stats;
  DdaProgram prog;
};

Out run(const std::vector<PathSegment>& segs, bool closed, double speed, double hz = 5000.0) {
  Out o;
  DdaOptions opt;
  opt.interrupt_hz = hz;
  o.prog = make_dda_program(segs, closed, kBlu, speed, opt);
  o.res = run_dda(o.prog, &o.rec, &o.stats);
  return o;
}

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
