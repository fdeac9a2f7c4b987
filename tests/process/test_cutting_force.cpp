// The lumped force model F = C v(t - tau), C = K b a (Elbestawi 1980, Sec. 4.4, Eq. 4.2-4.4) against the thesis's
// worked numbers (Sec. 4.4 and case A of Sec. 4.5), which are printed rounded.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/error.hpp"
#include "process/cutting_force.hpp"

namespace tu_process_test_cutting_force {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::process;

namespace {
constexpr double kMm = 1e-3;
constexpr double kRpm = 2 * std::numbers::pi / 60;
constexpr double kKUnit = 1e9;   // N/mm^2 per mm/s in N s/m^3
constexpr double kCUnit = 1e3;   // N/(mm/s) in N s/m
}  // namespace

// Sec. 4.4: d = 20 mm, 4 teeth, N = 500 rpm, tau = 0.030 s; f_t = 0.1 mm, a = 20 mm, b = 10 mm, F = 4200 N:
// v = 3.33 mm/s, K = 6.3 N/mm^2/(mm/s), C = 1260 N/(mm/s).
TEST(ProcessCuttingForce, ElbestawiSec44) {
  const double tau = tooth_period(4, 500 * kRpm);
  EXPECT_NEAR(tau, 0.030, 1e-12);
  const LumpedForceModel m = calibrate_lumped_model(4200, 0.1 * kMm, 10 * kMm, 20 * kMm, tau);
  EXPECT_NEAR(m.K / kKUnit, 6.3, 0.01 * 6.3);
  EXPECT_NEAR(m.C(10 * kMm, 20 * kMm) / kCUnit, 1260, 0.01 * 1260);
  // and back: at 3.33 mm/s steady, the force is the 4200 N it was calibrated on
  EXPECT_NEAR(m.force(10 * kMm, 20 * kMm, [](double) { return 0.1 * kMm / 0.030; }, 1.0), 4200, 1e-9);
}

// The force follows the speed one tooth period late (Eq. 4.2): a speed step at t = 0 reaches the force at tau.
TEST(ProcessCuttingForce, ForceLagsTheSpeedByOneToothPeriod) {
  const LumpedForceModel m{6.3 * kKUnit, 0.030};
  auto v = [](double t) { return t >= 0 ? 5 * kMm : 1 * kMm; };
  const double b = 10 * kMm, a = 20 * kMm;
  EXPECT_NEAR(m.force(b, a, v, 0.029), 6.3 * 10 * 20 * 1, 1e-9);   // N/mm^2/(mm/s) * mm * mm * mm/s
  EXPECT_NEAR(m.force(b, a, v, 0.030), 6.3 * 10 * 20 * 5, 1e-9);
}

// Case A (Sec. 4.5): F = 205 a b (x(t) - x(t - tau)), 205 N/mm^3, a = 20 mm, tau = 0.030 s; the rapid phase at
// 12.7 mm/s with b = 2.5 mm: 205 * 20 * 2.5 * 12.7 * 0.030 = 3905.25 N (printed 3900); at the step to b = 10 mm,
// still at 12.7 mm/s, four times that, 15621 N (printed 15,600).
TEST(ProcessCuttingForce, ElbestawiCaseA) {
  const LumpedForceModel m = lumped_model_from_specific_force(205 / (kMm * kMm * kMm), 0.030);
  const auto F = lumped_forces(m, {2.5 * kMm, 10 * kMm}, 20 * kMm, 12.7 * kMm);
  ASSERT_EQ(F.size(), 2u);
  EXPECT_NEAR(F[0], 3900, 0.01 * 3900);
  EXPECT_NEAR(F[1], 15600, 0.01 * 15600);
  EXPECT_NEAR(F[0], 3905.25, 1e-6);
  EXPECT_NEAR(F[1], 15621.0, 1e-6);
}

TEST(ProcessCuttingForce, BadInputIsRefused) {
  EXPECT_THROW(tooth_period(0, 100), InputError);
  EXPECT_THROW(calibrate_lumped_model(4200, 0, 1e-2, 2e-2, 0.03), InputError);
  EXPECT_THROW(lumped_model_from_specific_force(-1, 0.03), InputError);
  EXPECT_THROW(lumped_forces(LumpedForceModel{1, 0.03}, {std::nan("")}, 0.02, 0.01), InputError);
}

TEST(ProcessCuttingForce, OutOfRangeNumbersAreRefusedNotInfinite) {
  EXPECT_THROW(tooth_period(4, 1e-320), InputError);
  EXPECT_THROW(calibrate_lumped_model(1e300, 1e-300, 1e-3, 1e-3, 1.0), InputError);
  EXPECT_THROW(lumped_forces(LumpedForceModel{1e300, 0.03}, {1e200}, 1e200, 1.0), InputError);
}

}  // namespace tu_process_test_cutting_force
