// The machine models of Ch. 5 and App. F, each against an independent form: the worm and screw factors against
// the textbook efficiency formulas, the Table F.1 coefficients against their closed forms and the thesis's
// 1.17632, the pull-out formula against Eq. 5.17 written out, the tabulated curve's interpolation, the grinding
// force against Eq. 5.22-5.23.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/dynamics_helpers.hpp"
#include "machine/dynamics/mechanics.hpp"
#include "machine/dynamics/stepper.hpp"

namespace tu_machine_dynamics_test_dynamics_model {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {
constexpr double kPi = std::numbers::pi;
}

TEST(Mechanics, WormFactorWithoutFrictionIsTheReduction) {
  for (double k : {10.0, 40.0, 60.0})
    for (double rw : {0.005, 0.012}) {
      WormGeometry w{rw, 0.04, 14.5 * kPi / 180, 0.0, {}};
      EXPECT_NEAR(worm_factor(w, k), 1.0 / k, 1e-15) << k << " " << rw;
    }
}

TEST(Mechanics, WormFactorMatchesTheEfficiencyForm) {
  // worm driving the gear: efficiency e = (cos phi_n - f tan lambda) / (cos phi_n + f cot lambda), K1 = 1 / (k e)
  const double k = 40.0, rw = 0.01, rg = 0.05, phi = 20.0 * kPi / 180;
  const double lambda = std::atan(rg / (k * rw));
  for (double f : {0.02, 0.05, 0.1}) {
    const double e = (std::cos(phi) - f * std::tan(lambda)) / (std::cos(phi) + f / std::tan(lambda));
    EXPECT_NEAR(worm_factor({rw, rg, phi, f, {}}, k), 1.0 / (k * e), 1e-14) << f;
  }
  // a lead angle given as well must agree with the radii and the reduction
  WormGeometry g{rw, rg, phi, 0.05, {}};
  g.lead_angle = lambda;
  EXPECT_DOUBLE_EQ(worm_factor(g, k), worm_factor({rw, rg, phi, 0.05, {}}, k));
  g.lead_angle = 1.05 * lambda;
  EXPECT_THROW(worm_factor(g, k), InputError);
  // a friction high enough to lock the drive is refused
  EXPECT_THROW(worm_factor({rw, rg, phi, 50.0, {}}, 1.0), InputError);
  EXPECT_THROW(worm_factor({0.0, rg, phi, 0.1, {}}, k), InputError);
}

TEST(Mechanics, ScrewFactorMatchesThePowerScrewTorque) {
  const double l = 0.00127, rs = 0.006;
  EXPECT_NEAR(screw_factor({l, rs, 0.0, 0.0, {}}), l / (2 * kPi), 1e-18);
  EXPECT_NEAR(screw_factor({l, rs, 14.5 * kPi / 180, 0.0, {}}), l / (2 * kPi), 1e-18);
  // torque to raise a load F: T = F d_m/2 (l + pi f d_m sec a_n) / (pi d_m - f l sec a_n), tan a_n = tan a cos lambda
  const double dm = 2 * rs, lambda = std::atan(l / (kPi * dm));
  for (double a : {0.0, 14.5 * kPi / 180, 30.0 * kPi / 180})
    for (double f : {0.08, 0.15}) {
      const double an = std::atan(std::tan(a) * std::cos(lambda)), sec = 1.0 / std::cos(an);
      const double expect = dm / 2 * (l + kPi * f * dm * sec) / (kPi * dm - f * l * sec);
      EXPECT_NEAR(screw_factor({l, rs, a, f, {}}), expect, 1e-15) << a << " " << f;
    }
  EXPECT_THROW(screw_factor({l, rs, 0.0, -0.1, {}}), InputError);
  ScrewGeometry sg{l, rs, 14.5 * kPi / 180, 0.1, {}};
  sg.helix_angle = 1.001 * lambda;
  EXPECT_NEAR(screw_factor(sg), screw_factor({l, rs, 14.5 * kPi / 180, 0.1, {}}), 1e-6 * screw_factor(sg));
  sg.helix_angle = 2 * lambda;
  EXPECT_THROW(screw_factor(sg), InputError);
}

TEST(Stepper, TableF1Coefficients) {
  // the fundamental of a +V / 0 / -V / 0 wave with +V held over a fraction w of the period is (4/pi) sin(pi w)
  EXPECT_NEAR(pullout_coefficient(Energisation::wave), 4 / kPi * std::sin(3 * kPi / 8), 1e-15);
  EXPECT_NEAR(pullout_coefficient(Energisation::full_two), 4 / kPi, 1e-15);
  EXPECT_NEAR(pullout_coefficient(Energisation::full_one), 4 / kPi * std::sin(kPi / 4), 1e-15);
  // the thesis's constant, to the digits it prints
  EXPECT_NEAR(pullout_coefficient(Energisation::wave), 1.17632, 0.5e-5);
  EXPECT_EQ(steps_per_cycle(Energisation::wave), 8);
  EXPECT_EQ(steps_per_cycle(Energisation::full_one), 4);
  EXPECT_EQ(steps_per_cycle(Energisation::full_two), 4);
  // in every scheme the two phases carry the same fundamental a quarter cycle apart (a two-phase motor)
  for (Energisation e : {Energisation::wave, Energisation::full_one, Energisation::full_two}) {
    const Fundamental a = phase_fundamental(table_f1(e), 0), b = phase_fundamental(table_f1(e), 1);
    EXPECT_NEAR(a.amplitude, b.amplitude, 1e-15) << to_string(e);
    EXPECT_NEAR(std::abs(std::remainder(a.phase - b.phase, 2 * kPi)), kPi / 2, 1e-12) << to_string(e);
  }
}

TEST(Stepper, PulloutIsEquation517) {
  const ElectricalMotor m = thesis_motor();
  EXPECT_EQ(m.steps_per_rev(), 400.0);
  const double c = 4 / kPi * std::sin(3 * kPi / 8);
  for (double f : {0.0, 10.0, 400.0, 2000.0, 5500.0, 20000.0}) {
    const double w = 2 * kPi * 50 * f / 400;  // electrical rad/s: N_s times the shaft's
    const double z2 = 6.5 * 6.5 + w * w * 6.3e-4 * 6.3e-4;
    const double expect = c * 24 * 0.0759 / std::sqrt(z2) - 0.068 * w * 6.5 * 0.0759 / (50 * z2);
    EXPECT_NEAR(m.pullout_at_rate(f), expect, 1e-15) << f;
  }
  // at standstill: c1 V K_T / R_a
  EXPECT_NEAR(m.pullout(0.0), c * 24 * 0.0759 / 6.5, 1e-15);
  // the pull-out torque falls with the step rate
  double prev = m.pullout_at_rate(0.0);
  for (double f = 100; f <= 20000; f += 100) {
    const double t = m.pullout_at_rate(f);
    EXPECT_LT(t, prev) << f;
    prev = t;
  }
}

TEST(Stepper, CurveIsMonotoneAndRefusesToExtrapolate) {
  PulloutCurve c({0, 200, 500, 1000, 2000, 4000}, {0.40, 0.39, 0.35, 0.28, 0.18, 0.09});
  EXPECT_DOUBLE_EQ(c.at(500), 0.35);
  EXPECT_DOUBLE_EQ(c.at(4000), 0.09);
  double prev = c.at(0);
  for (double f = 5; f <= 4000; f += 5) {
    const double t = c.at(f);
    EXPECT_LE(t, prev + 1e-15) << f;
    prev = t;
  }
  EXPECT_THROW(c.at(4000.5), OutsideCurveError);
  PulloutCurve from100({100, 1000}, {0.3, 0.2});  // two points: linear
  EXPECT_NEAR(from100.at(550), 0.25, 1e-15);
  EXPECT_THROW(from100.at(50), OutsideCurveError);
  EXPECT_THROW(PulloutCurve({0, 100, 100}, {0.3, 0.2, 0.1}), InputError);
  EXPECT_THROW(PulloutCurve({0, 100}, {0.3, -0.2}), InputError);
  EXPECT_THROW(PulloutCurve({0}, {0.3}), InputError);
  StepperMotor m = make_curve_motor(c, 400.0, 3000.0);
  EXPECT_DOUBLE_EQ(m.pullout_at_rate(1000), 0.28);
}

TEST(Load, GrindingForceIsEquation522) {
  const GrindingSpec g = thesis_grinding();
  const double Kc = 6.46e10 * std::sqrt(1 + 1.66 * 1.66) * 0.0254e-3 * 0.635e-2 / 16.62;
  EXPECT_NEAR(g.K_c(), Kc, 1e-9 * Kc);
  const Load l = grinding(g);
  const ToolForce f = l.force(0.0, 0.0152);
  // F_c = K_c V at atan(c1) to the surface: tangential F_c cos, normal F_c sin, their ratio c1
  EXPECT_NEAR(std::hypot(f.tangential, f.normal), Kc * 0.0152, 1e-12);
  EXPECT_NEAR(f.normal / f.tangential, 1.66, 1e-13);
  // tangential force = specific energy times chip cross-section rate: k_c d w V / V_tool
  EXPECT_NEAR(f.tangential, 6.46e10 * 0.0254e-3 * 0.635e-2 * 0.0152 / 16.62, 1e-12);
  LoadSpec bad;
  bad.kind = LoadKind::grinding;
  EXPECT_THROW(make_load(bad), InputError);
}

}  // namespace tu_machine_dynamics_test_dynamics_model
