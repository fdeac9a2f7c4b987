// The constant-force schedule on a circle (the same engagement all round): the speed that gives the nominal force
// (computed here from the mean force's closed form for slotting), the entry at a third of it over the entry
// length and the ramp of V^2 after it, the top speed when it binds first, the largest acceleration between stations.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "process/constant_force.hpp"

namespace tu_process_test_constant_force {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::process;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMm = 1e-3;

// Slotting (a = 2R) with straight flutes: engaged over [0, pi] wherever the path goes, whatever its curvature;
// the mean force per f_t is (N b / 4) (-K_r, K_t) (x, y), |F| = N b f_t sqrt(K_t^2 + K_r^2) / 4, and the edge's
// feed on the circle is (rho_c + R - a/2) / rho_c = 1 of the centre's inside a hole (tool left, material right).
MillingPathSpec slot_spec() {
  MillingPathSpec s;
  s.cutter = {2, 5 * kMm, 0.0, 4 * kMm, 800e6, 300e6, 0.0};
  s.radial_width_m = 10 * kMm;
  s.spindle_speed_rad_s = 100.0;
  s.tool_side = 1;
  s.stations = 400;
  return s;
}

}  // namespace

TEST(ConstantForce, HoldsTheNominalForceWithAPlannedEntry) {
  const MillingPath mp(*make_circle({0, 0}, 30 * kMm), slot_spec());
  const double per_ft = 2 * 4 * kMm * std::hypot(800e6, 300e6) / 4;  // N per m of feed per tooth
  const double n = 100.0 / (2 * kPi);                                // rev/s
  const double F = 200.0, V = F / per_ft * 2 * n;                    // f_t = V / (N n)
  ConstantForceLimits lim;
  lim.nominal_force_N = F;
  lim.max_speed = 1.0;
  lim.entry_length_m = 10 * kMm;
  const ConstantForceSchedule s = constant_force_schedule(mp, lim);
  ASSERT_GT(s.stations.size(), 100u);
  for (const FeedStation& f : s.stations) {
    if (f.s <= 10 * kMm) {
      EXPECT_NEAR(f.v, V / 3, 1e-9 * V) << f.s;
      EXPECT_EQ(f.binding, FeedBinding::entry);
    } else if (f.s < 20 * kMm) {
      // V^2 from (V/3)^2 towards the top speed, linear over the next 10 mm, until it meets V
      const double ramp = std::sqrt(V * V / 9 + (f.s - 10 * kMm) / (10 * kMm) * (1.0 - V * V / 9));
      EXPECT_NEAR(f.v, std::min(ramp, V), 1e-9 * V) << f.s;
    } else {
      EXPECT_NEAR(f.v, V, 1e-9 * V) << f.s;
      EXPECT_EQ(f.binding, FeedBinding::nominal_force);
    }
  }
  EXPECT_EQ(s.stretches.front().binding, FeedBinding::entry);
  EXPECT_EQ(s.stretches.back().binding, FeedBinding::nominal_force);
  EXPECT_NEAR(s.stretches.back().s1, 2 * kPi * 30 * kMm, 1e-12);
  // time: the sum over intervals of 2 h / (V0 + V1), at least the length over V
  EXPECT_GT(s.total_time_s, 2 * kPi * 30 * kMm / V);

  // a top speed below V binds instead
  lim.max_speed = 0.5 * V;
  lim.entry_length_m = 0.0;
  const ConstantForceSchedule t = constant_force_schedule(mp, lim);
  for (const FeedStation& f : t.stations) {
    EXPECT_NEAR(f.v, 0.5 * V, 1e-12);
    EXPECT_EQ(f.binding, FeedBinding::speed);
  }
  EXPECT_NEAR(t.total_time_s, 2 * kPi * 30 * kMm / (0.5 * V), 1e-9);

  // a feed-per-tooth limit below the nominal force's feed
  lim.max_speed = 1.0;
  lim.feed_per_tooth_m = 0.25 * V / (2 * n);
  for (const FeedStation& f : constant_force_schedule(mp, lim).stations) {
    EXPECT_NEAR(f.v, 0.25 * V, 1e-9 * V);
    EXPECT_EQ(f.binding, FeedBinding::feed_per_tooth);
  }
}

TEST(ConstantForce, KeepsTheLargestAcceleration) {
  const MillingPath mp(*make_circle({0, 0}, 30 * kMm), slot_spec());
  ConstantForceLimits lim;
  lim.nominal_force_N = 2000.0;
  lim.max_speed = 0.05;
  lim.entry_length_m = 5 * kMm;
  lim.entry_fraction = 0.1;
  lim.max_acceleration = 0.01;
  const ConstantForceSchedule s = constant_force_schedule(mp, lim);
  bool limited = false;
  for (size_t i = 1; i < s.stations.size(); ++i) {
    const FeedStation &a = s.stations[i - 1], &b = s.stations[i];
    EXPECT_LE(std::abs(b.v * b.v - a.v * a.v), 2 * 0.01 * (b.s - a.s) * (1 + 1e-9));
    limited |= b.binding == FeedBinding::acceleration;
  }
  EXPECT_TRUE(limited);
}

TEST(ConstantForce, RefusesBadLimits) {
  ConstantForceLimits lim;
  lim.nominal_force_N = 0.0;
  lim.max_speed = 1.0;
  EXPECT_THROW(check_constant_force_limits(lim), InputError);
  lim.nominal_force_N = 10.0;
  lim.entry_fraction = 0.0;
  EXPECT_THROW(check_constant_force_limits(lim), InputError);
}

}  // namespace tu_process_test_constant_force
