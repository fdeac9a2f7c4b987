// The engagement along a contour: the engaged angle from the cutter circle and the stock's boundary, found here by
// bisection on the circles themselves (not by the model's formula); the forces along a circular path.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "process/milling_path.hpp"

namespace tu_process_test_milling_path {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::process;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMm = 1e-3;

// The engaged angle by geometry: the cutter's centre at distance rc from the arc's centre O; a point of the cutter
// at angle psi from the direction towards the stock is in the stock when it lies beyond the finished contour's
// offset by a: |P| > rho - a inside a hole (concave), |P| < rho + a outside a boss (convex). The largest such psi
// by bisection (the in-stock set is an interval about psi = 0).
double engaged_by_bisection(double R, double a, double rc, bool concave) {
  auto in_stock = [&](double psi) {
    if (concave) {
      const double rho = rc + R;  // the centre is inside the hole; towards the stock is away from O
      const double d = std::sqrt(rc * rc + R * R + 2 * rc * R * std::cos(psi));
      return d > rho - a;
    }
    const double rho = rc - R;  // outside the boss; towards the stock is towards O
    const double d = std::sqrt(rc * rc + R * R - 2 * rc * R * std::cos(psi));
    return d < rho + a;
  };
  if (in_stock(kPi)) return kPi;
  double lo = 0.0, hi = kPi;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (in_stock(mid) ? lo : hi) = mid;
  }
  return lo;
}

SliceCutter cutter() {
  SliceCutter c;
  c.teeth = 4;
  c.radius_m = 6.35 * kMm;
  c.helix_rad = 38.0 * kPi / 180.0;
  c.axial_depth_m = 5 * kMm;
  c.K_t = 800e6;
  c.K_r = 240e6;
  return c;
}

}  // namespace

TEST(MillingPath, EngagedAngleAgainstTheCircles) {
  const double R = 6.35 * kMm;
  for (double a : {0.5 * kMm, 2 * kMm, R, 10 * kMm}) {
    // straight: acos(1 - a/R)
    EXPECT_NEAR(engaged_angle(R, a, 0.0, true), std::acos(1 - std::min(a, 2 * R) / R), 1e-12);
    for (double rc : {8 * kMm, 20 * kMm, 100 * kMm}) {
      // a path turning left at radius rc; the material on the right: the centre of curvature on the tool's side
      // (a hole, concave); on the left: on the material's side (a boss, convex)
      const double k = 1.0 / rc;
      EXPECT_NEAR(engaged_angle(R, a, k, false), engaged_by_bisection(R, a, rc, true), 1e-9) << a << " " << rc;
      if (rc >= R) {
        EXPECT_NEAR(engaged_angle(R, a, k, true), engaged_by_bisection(R, a, rc, false), 1e-9) << a << " " << rc;
      }
      // turning right mirrors it
      EXPECT_NEAR(engaged_angle(R, a, -k, true), engaged_angle(R, a, k, false), 1e-15);
      // concave engages more than straight, convex less
      if (a < 2 * R) {
        EXPECT_GT(engaged_angle(R, a, k, false), engaged_angle(R, a, 0.0, false));
        EXPECT_LT(engaged_angle(R, a, k, true), engaged_angle(R, a, 0.0, false));
      }
    }
  }
  // a hole not much larger than the cutter, with more stock than its radius: all of the front half
  EXPECT_EQ(engaged_angle(R, 8 * kMm, 1.0 / (1 * kMm), false), kPi);
}

TEST(MillingPath, ModeFromTheMaterialsSideAndTheSpindle) {
  EXPECT_EQ(milling_mode(true, true), MillingMode::up);
  EXPECT_EQ(milling_mode(false, true), MillingMode::down);
  EXPECT_EQ(milling_mode(true, false), MillingMode::down);
  EXPECT_EQ(milling_mode(false, false), MillingMode::up);
}

// Inside a hole: the centre runs counter-clockwise on a circle of radius rc, the tool on its left (towards the
// centre), the material on the right: a concave stretch everywhere, down milling with an M03 spindle.
TEST(MillingPath, AlongAHole) {
  const double rc = 20 * kMm, a = 1.5 * kMm;
  MillingPathSpec spec;
  spec.cutter = cutter();
  spec.radial_width_m = a;
  spec.spindle_speed_rad_s = 2000.0 * 2.0 * kPi / 60.0;
  spec.tool_side = 1;
  spec.stations = 50;
  const MillingPath mp(*make_circle({0, 0}, rc), spec);
  EXPECT_EQ(mp.mode(), MillingMode::down);
  EXPECT_NEAR(mp.length(), 2 * kPi * rc, 1e-12);
  const double psi = engaged_by_bisection(spec.cutter.radius_m, a, rc, true);
  const double scale = (rc + spec.cutter.radius_m - 0.5 * a) / rc;  // the edge at mid-width, over the centre
  const double V = 20e-3;  // 20 mm/s at 4 teeth, 2000 rev/min: f_t = 0.15 mm
  EXPECT_NEAR(mp.feed_per_tooth(V), 0.15 * kMm, 1e-15);
  EXPECT_NEAR(mp.speed_for_feed_per_tooth(0.15 * kMm), V, 1e-15);
  const CutterForce m = mean_force(spec.cutter, immersion_for(MillingMode::down, psi), 0.15 * kMm * scale);
  for (double s : {0.0, 0.013, 0.1, mp.length()}) {
    const MillingForceAt f = mp.at(s, V);
    EXPECT_NEAR(f.engaged_angle_rad, psi, 1e-9);
    EXPECT_NEAR(f.feed_force_N, -m.x, 1e-6 * std::abs(m.x));
    EXPECT_NEAR(f.normal_force_N, m.y, 1e-6 * std::abs(m.y));  // down milling: the material on -y
    EXPECT_NEAR(f.mean_resultant_N, std::hypot(m.x, m.y), 1e-6 * std::hypot(m.x, m.y));
    EXPECT_GT(f.normal_force_N, 0.0);  // the cut pushes the tool off the wall
    EXPECT_LT(f.feed_force_N, 0.0);    // and, climbing, draws it along the feed
    EXPECT_GE(f.peak_resultant_N, f.mean_resultant_N);
  }
  // the stations cover the path in order
  for (size_t i = 1; i < mp.stations().size(); ++i) EXPECT_GE(mp.stations()[i].s, mp.stations()[i - 1].s);
}

// The same circle with the tool outside (on the right of a counter-clockwise path): a boss, less engaged than a
// straight wall.
TEST(MillingPath, AroundABoss) {
  const double rc = 20 * kMm, a = 1.5 * kMm;
  MillingPathSpec spec;
  spec.cutter = cutter();
  spec.radial_width_m = a;
  spec.spindle_speed_rad_s = 200.0;
  spec.tool_side = -1;
  spec.stations = 20;
  const MillingPath mp(*make_circle({0, 0}, rc), spec);
  EXPECT_EQ(mp.mode(), MillingMode::up);
  EXPECT_NEAR(mp.stations()[3].engaged_angle, engaged_by_bisection(spec.cutter.radius_m, a, rc, false), 1e-9);
  EXPECT_LT(mp.stations()[3].engaged_angle, straight_engaged_angle(a, spec.cutter.radius_m));
  // milling up, the cut pushes the tool back against its feed
  EXPECT_GT(mp.at(0.05, 0.01).feed_force_N, 0.0);
}

TEST(MillingPath, RefusesABadSpec) {
  MillingPathSpec spec;
  spec.cutter = cutter();
  spec.radial_width_m = 20 * kMm;  // wider than the 12.7 mm cutter
  spec.spindle_speed_rad_s = 200.0;
  EXPECT_THROW(check_milling_path_spec(spec), InputError);
  spec.radial_width_m = 1 * kMm;
  EXPECT_NO_THROW(check_milling_path_spec(spec));
  spec.spindle_speed_rad_s = 0;
  EXPECT_THROW(check_milling_path_spec(spec), InputError);
}

}  // namespace tu_process_test_milling_path
