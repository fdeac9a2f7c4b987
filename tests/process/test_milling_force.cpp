// The helical tooth-slice force (Elbestawi 1980, Eq. 5.1-5.8) against cases computed here without the model:
// slotting with straight flutes (the mean tangential force N K_t b f_t / pi), a cutter whose helix spreads the
// teeth evenly over the depth (a force that does not vary), half immersion by a numerical integration of the chip
// over the engaged angle written in this file.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/error.hpp"
#include "process/milling_force.hpp"

namespace tu_process_test_milling_force {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::process;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMm = 1e-3;

SliceCutter cutter(int teeth, double helix_deg, double b) {
  SliceCutter c;
  c.teeth = teeth;
  c.radius_m = 6.35 * kMm;
  c.helix_rad = helix_deg * kPi / 180.0;
  c.axial_depth_m = b;
  c.K_t = 800e6;
  c.K_r = 240e6;
  return c;
}

// The model's force averaged over a revolution by sampling it (which: 0 x, 1 y, 2 z).
double average(const SliceCutter& c, const Immersion& im, double ft, int samples, int which) {
  const int slices = slice_count(c);
  double sum = 0.0;
  for (int k = 0; k < samples; ++k) {
    const CutterForce f = slice_force(c, im, ft, 2.0 * kPi * (k + 0.5) / samples, slices);
    sum += which == 0 ? f.x : which == 1 ? f.y : f.z;
  }
  return sum / samples;
}

}  // namespace

TEST(MillingForce, StraightEngagedAngle) {
  EXPECT_NEAR(straight_engaged_angle(6.35 * kMm, 6.35 * kMm), kPi / 2, 1e-15);
  EXPECT_NEAR(straight_engaged_angle(12.7 * kMm, 6.35 * kMm), kPi, 1e-15);
  EXPECT_NEAR(straight_engaged_angle(20 * kMm, 6.35 * kMm), kPi, 1e-15);
  EXPECT_NEAR(straight_engaged_angle(6.35 * kMm * (1 - std::cos(0.3)), 6.35 * kMm), 0.3, 1e-12);
  EXPECT_EQ(straight_engaged_angle(0.0, 1.0), 0.0);
  const Immersion up = immersion_for(MillingMode::up, 1.0), down = immersion_for(MillingMode::down, 1.0);
  EXPECT_EQ(up.entry, 0.0);
  EXPECT_EQ(up.exit, 1.0);
  EXPECT_NEAR(down.entry, kPi - 1.0, 1e-15);
  EXPECT_EQ(down.exit, kPi);
}

// Slotting, straight flutes: every tooth in [0, pi] cuts h = f_t sin(phi); the tangential force of one tooth
// averaged over a revolution is (1/2pi) int_0^pi K_t b f_t sin(phi) dphi = K_t b f_t / pi, N teeth: N K_t b f_t / pi.
// The test takes each tooth's tangential force back from the model's F_x, F_y (F_t = -F_x cos(phi) + F_y sin(phi),
// which removes the radial part) and averages it over a revolution.
TEST(MillingForce, SlottingStraightFlutesMeanTangentialForce) {
  const SliceCutter c = cutter(4, 0.0, 10 * kMm);
  const Immersion slot{0.0, kPi};
  const double ft = 0.1 * kMm;
  const int samples = 36000;
  double torque_force = 0.0;  // sum over teeth of the tangential force, averaged
  for (int k = 0; k < samples; ++k) {
    const double theta = 2.0 * kPi * (k + 0.5) / samples;
    for (int j = 0; j < c.teeth; ++j) {
      const CutterForce f = slice_force(c, slot, ft, theta, 1, j);
      double phi = std::fmod(theta + j * 2.0 * kPi / c.teeth, 2.0 * kPi);
      torque_force += -f.x * std::cos(phi) + f.y * std::sin(phi);
    }
  }
  torque_force /= samples;
  const double expected = c.teeth * c.K_t * c.axial_depth_m * ft / kPi;
  EXPECT_NEAR(torque_force, expected, 1e-4 * expected);
  // slotting: int_0^pi (-K_t sin cos - K_r sin^2) dphi = -K_r pi / 2, times N b f_t / (2 pi)
  const CutterForce m = mean_force(c, slot, ft);
  EXPECT_NEAR(m.x, -c.teeth * c.axial_depth_m * ft * c.K_r / 4.0, 1e-9);
  // int_0^pi (K_t sin^2 - K_r sin cos) = K_t pi / 2
  EXPECT_NEAR(m.y, c.teeth * c.axial_depth_m * ft * c.K_t / 4.0, 1e-9);
}

// When the helix lags the top of the cut behind the tip by exactly one tooth pitch (b tan(lambda) / r = 2 pi / N),
// every angle of the engagement holds the same length of cutting edge at every moment: the force does not vary
// with the rotation. Slotting and a partial immersion both.
TEST(MillingForce, OnePitchOfHelixOverTheDepthGivesAConstantForce) {
  const int N = 4;
  const double lambda = 30.0 * kPi / 180.0;
  const double r = 6.35 * kMm;
  const double b = 2.0 * kPi / N * r / std::tan(lambda);
  SliceCutter c = cutter(N, 30.0, b);
  for (const Immersion im : {Immersion{0.0, kPi}, Immersion{0.0, 1.2}, Immersion{kPi - 0.7, kPi}}) {
    const int slices = 4000;
    const CutterForce m = mean_force(c, im, 0.1 * kMm);
    double lo = 1e300, hi = -1e300;
    for (int k = 0; k < 90; ++k) {
      const CutterForce f = slice_force(c, im, 0.1 * kMm, 2.0 * kPi / N * k / 90.0 + 0.0123, slices);
      lo = std::min(lo, f.y);
      hi = std::max(hi, f.y);
      EXPECT_NEAR(f.x, m.x, 2e-3 * std::hypot(m.x, m.y));
      EXPECT_NEAR(f.y, m.y, 2e-3 * std::hypot(m.x, m.y));
    }
    EXPECT_LT(hi - lo, 2e-3 * std::hypot(m.x, m.y));
  }
}

// Half immersion, up and down milling, 38 deg helix: the mean force by Simpson's rule over the engaged angle of
// the slice forces K_t b h and K_r b h written out here, against the model averaged over a revolution and its
// closed form. The helix does not change the mean (each slice is the straight cutter turned by its lag).
TEST(MillingForce, HalfImmersionMeanByIndependentQuadrature) {
  const SliceCutter c = cutter(4, 38.0, 8 * kMm);
  const double ft = 0.05 * kMm;
  for (MillingMode mode : {MillingMode::up, MillingMode::down}) {
    const Immersion im = immersion_for(mode, kPi / 2);
    const int n = 2000;  // Simpson intervals
    double sx = 0, sy = 0;
    for (int i = 0; i <= n; ++i) {
      const double phi = im.entry + (im.exit - im.entry) * i / n;
      const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      const double h = ft * std::sin(phi);
      const double Ft = c.K_t * c.axial_depth_m * h, Fr = c.K_r * c.axial_depth_m * h;
      sx += w * (-Ft * std::cos(phi) - Fr * std::sin(phi));
      sy += w * (Ft * std::sin(phi) - Fr * std::cos(phi));
    }
    const double dphi = (im.exit - im.entry) / n;
    const double ex = c.teeth / (2 * kPi) * sx * dphi / 3, ey = c.teeth / (2 * kPi) * sy * dphi / 3;
    const CutterForce m = mean_force(c, im, ft);
    EXPECT_NEAR(m.x, ex, 1e-9 * std::abs(ex) + 1e-12);
    EXPECT_NEAR(m.y, ey, 1e-9 * std::abs(ey));
    // the model's instantaneous force, averaged over a revolution
    EXPECT_NEAR(average(c, im, ft, 7200, 0), ex, 2e-3 * std::hypot(ex, ey));
    EXPECT_NEAR(average(c, im, ft, 7200, 1), ey, 2e-3 * std::hypot(ex, ey));
  }
}

// The axial force: K_a b h per slice, mean N b f_t K_a (cos(entry) - cos(exit)) / (2 pi): slotting gives
// N b f_t K_a / pi.
TEST(MillingForce, AxialForce) {
  SliceCutter c = cutter(2, 0.0, 5 * kMm);
  c.K_a = 100e6;
  const double ft = 0.1 * kMm;
  EXPECT_NEAR(mean_force(c, {0.0, kPi}, ft).z, 2 * 5 * kMm * ft * 100e6 / kPi, 1e-9);
  EXPECT_NEAR(average(c, {0.0, kPi}, ft, 36000, 2), 2 * 5 * kMm * ft * 100e6 / kPi, 1e-3);
}

// Peaks: one straight tooth in a slot peaks at phi = 90 deg where h = f_t, F = b f_t sqrt(K_t^2 + K_r^2);
// two teeth 180 deg apart in a slot are never both cutting except at the ends.
TEST(MillingForce, PeaksOfAStraightToothInASlot) {
  const SliceCutter c = cutter(2, 0.0, 5 * kMm);
  const double ft = 0.1 * kMm;
  const ForcePeaks p = force_peaks(c, {0.0, kPi}, ft);
  const double single = c.axial_depth_m * ft * std::hypot(c.K_t, c.K_r);
  EXPECT_NEAR(p.tooth, single, 1e-5 * single);  // sampled every 0.25 deg: within 1 - cos(0.125 deg)
  EXPECT_NEAR(p.resultant, single, 1e-5 * single);
  // F_y = b f_t (K_t sin^2 - K_r sin cos): its largest |value| over [0, pi] by a fine search here
  double ymax = 0;
  for (int i = 0; i <= 200000; ++i) {
    const double phi = kPi * i / 200000;
    ymax = std::max(ymax, std::abs(c.axial_depth_m * ft * (c.K_t * std::sin(phi) * std::sin(phi) -
                                                           c.K_r * std::sin(phi) * std::cos(phi))));
  }
  EXPECT_NEAR(p.normal, ymax, 1e-4 * ymax);
  // linear in the feed per tooth
  const ForcePeaks p2 = force_peaks(c, {0.0, kPi}, 2 * ft);
  EXPECT_NEAR(p2.resultant, 2 * p.resultant, 1e-9 * p.resultant);
}

TEST(MillingForce, RefusesACutterItCannotModel) {
  SliceCutter c = cutter(4, 30, 5 * kMm);
  EXPECT_NO_THROW(check_slice_cutter(c));
  c.helix_rad = kPi / 2;
  EXPECT_THROW(check_slice_cutter(c), InputError);
  c = cutter(4, 30, 5 * kMm);
  c.K_t = 0;
  EXPECT_THROW(check_slice_cutter(c), InputError);
  c = cutter(0, 30, 5 * kMm);
  EXPECT_THROW(check_slice_cutter(c), InputError);
  c = cutter(4, 30, -1);
  EXPECT_THROW(check_slice_cutter(c), InputError);
}

// The peaks of a helical cutter (which force_peaks finds on a grid of whole-step slice lags) against the largest
// forces of the slice model itself, sampled every 0.05 deg with 400 slices: within 1 %.
TEST(MillingForce, HelicalPeaksAgainstTheSampledModel) {
  const SliceCutter c = cutter(4, 38.0, 6.35 * kMm);
  const double ft = 0.1 * kMm;
  for (MillingMode mode : {MillingMode::up, MillingMode::down})
    for (double psi : {0.4, 1.0, kPi}) {
      const Immersion im = immersion_for(mode, psi);
      const ForcePeaks p = force_peaks(c, im, ft);
      double res = 0, normal = 0, tooth = 0;
      for (int k = 0; k < 7200; ++k) {
        const double th = 2 * kPi * k / 7200;
        const CutterForce f = slice_force(c, im, ft, th, 400);
        res = std::max(res, std::hypot(f.x, f.y));
        normal = std::max(normal, std::abs(f.y));
        const CutterForce t = slice_force(c, im, ft, th, 400, 0);
        tooth = std::max(tooth, std::hypot(t.x, t.y));
      }
      EXPECT_NEAR(p.resultant, res, 0.01 * res) << psi;
      EXPECT_NEAR(p.normal, normal, 0.01 * res) << psi;
      EXPECT_NEAR(p.tooth, tooth, 0.01 * tooth) << psi;
    }
}

}  // namespace tu_process_test_milling_force
