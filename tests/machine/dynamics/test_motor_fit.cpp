// The Ceres fit of the electrical pull-out model: recovers known constants from exact points, resists outliers
// with its robust loss (where plain least squares is dragged), and refuses unusable input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/dynamics_helpers.hpp"
#include "machine/dynamics/motor_fit.hpp"

namespace tu_machine_dynamics_test_motor_fit {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {

std::vector<PulloutPoint> curve_points(const ElectricalMotor& m, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise);
  std::vector<PulloutPoint> pts;
  for (double f = 0; f <= 12000; f += 500) pts.push_back({f, m.pullout_at_rate(f) + n(rng)});
  return pts;
}

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

}  // namespace

TEST(MotorFit, RecoversTheConstantsFromExactPoints) {
  const ElectricalMotor truth = thesis_motor();
  for (Energisation e : {Energisation::wave, Energisation::full_two}) {
    ElectricalMotor t = truth;
    t.energisation = e;
    ElectricalMotor known = t;
    known.K_T = known.K_V = known.L_a = 0.0;  // ignored
    const MotorFitResult r = fit_electrical_motor(curve_points(t, 0.0, 1), known);
    EXPECT_LT(rel(r.motor.K_T, t.K_T), 1e-6) << to_string(e);
    EXPECT_LT(rel(r.motor.K_V, t.K_V), 1e-5) << to_string(e);
    EXPECT_LT(rel(r.motor.L_a, t.L_a), 1e-6) << to_string(e);
    EXPECT_LT(r.rms, 1e-8);
    for (bool o : r.outlier) EXPECT_FALSE(o);
  }
}

TEST(MotorFit, RobustLossResistsOutliers) {
  const ElectricalMotor truth = thesis_motor();
  std::vector<PulloutPoint> pts = curve_points(truth, 0.002, 7);
  pts[3].torque *= 0.6;   // a slipped brake reading
  pts[15].torque *= 1.5;  // a misread scale
  const MotorFitResult robust = fit_electrical_motor(pts, truth);
  MotorFitOptions plain_opt;
  plain_opt.loss = RobustLoss::none;
  const MotorFitResult plain = fit_electrical_motor(pts, truth, plain_opt);
  EXPECT_TRUE(robust.outlier[3]);
  EXPECT_TRUE(robust.outlier[15]);
  size_t flagged = 0;
  for (bool o : robust.outlier) flagged += o;
  EXPECT_EQ(flagged, 2u);
  // with 0.6 % noise K_V and L_a are strongly correlated (both shape the fall at speed): judge them by the standard
  // errors the fit reports
  ASSERT_TRUE(robust.K_T_sd && robust.K_V_sd && robust.L_a_sd);
  EXPECT_LT(std::abs(robust.motor.K_T - truth.K_T), 4 * *robust.K_T_sd);
  EXPECT_LT(std::abs(robust.motor.K_V - truth.K_V), 4 * *robust.K_V_sd);
  EXPECT_LT(std::abs(robust.motor.L_a - truth.L_a), 4 * *robust.L_a_sd);
  // the curve itself is well determined
  for (double f = 0; f <= 12000; f += 250)
    EXPECT_LT(std::abs(robust.motor.pullout_at_rate(f) - truth.pullout_at_rate(f)), 0.003) << f;
  // least squares without the robust loss is pulled further from the truth
  EXPECT_GT(std::abs(plain.motor.pullout_at_rate(1500) - truth.pullout_at_rate(1500)),
            std::abs(robust.motor.pullout_at_rate(1500) - truth.pullout_at_rate(1500)));
  EXPECT_GT(*robust.K_T_sd, 0.0);
  EXPECT_LT(*robust.K_T_sd, 0.01 * truth.K_T);
  // the residuals are model minus measurement
  for (size_t i = 0; i < pts.size(); ++i)
    EXPECT_NEAR(robust.residuals[i], robust.motor.pullout_at_rate(pts[i].rate_hz) - pts[i].torque, 1e-15);
}

TEST(MotorFit, RefusesUnusableInput) {
  const ElectricalMotor m = thesis_motor();
  EXPECT_THROW(fit_electrical_motor({{0, 0.3}, {100, 0.3}, {200, 0.29}}, m), InputError);             // too few
  EXPECT_THROW(fit_electrical_motor({{0, 0.3}, {0, 0.3}, {100, 0.29}, {100, 0.28}}, m), InputError);  // two rates
  EXPECT_THROW(fit_electrical_motor({{0, 0.3}, {100, -0.3}, {200, 0.29}, {300, 0.28}}, m), InputError);
  ElectricalMotor no_r = m;
  no_r.R_a = 0.0;
  EXPECT_THROW(fit_electrical_motor(curve_points(m, 0.0, 1), no_r), InputError);
}

}  // namespace tu_machine_dynamics_test_motor_fit
