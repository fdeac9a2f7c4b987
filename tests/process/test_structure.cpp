// The two-mass structure: G(s) against the equations of motion solved directly, its special cases (Eq. 2.6-2.7),
// the undamped modes against det(K - w^2 M) = 0.
#include <gtest/gtest.h>

#include <complex>

#include "cam/error.hpp"
#include "process/structure.hpp"
#include "tests/process/dunckley_cases.hpp"

namespace polarcam::test {
namespace tu_process_test_structure {  // named: the test files compile together

using C = std::complex<double>;
using process::TwoMassStructure;

// X_w / F_c from Eq. 2.2-2.3 transformed, solved as a 2x2 linear system by Cramer's rule (no expanded polynomial)
C direct_compliance(const TwoMassStructure& p, C s) {
  const C a11 = p.M_m * s * s + (p.C_m + p.C_w) * s + p.K_m + p.K_w, a12 = -(p.C_w * s + p.K_w);
  const C a21 = -(p.C_w * s + p.K_w), a22 = p.M_w * s * s + p.C_w * s + p.K_w;
  // [a11 a12; a21 a22] [X_m; X_w] = [0; F]: X_w = a11 F / det
  return a11 / (a11 * a22 - a12 * a21);
}

TEST(ChatterStructure, ComplianceSolvesTheEquationsOfMotion) {
  for (const DunckleyCase& c : kDunckleyCases) {
    const TwoMassStructure p = dunckley_structure(c);
    const process::TransferFunction g = process::workpiece_compliance(p);
    for (C s : {C(0.0, 0.0), C(0.0, 100.0), C(0.0, c.paper_rad_s), C(-3.0, 2500.0), C(5.0, 40.0), C(0.0, 9000.0)}) {
      const C want = direct_compliance(p, s), got = g(s);
      EXPECT_LT(std::abs(got - want), 1e-9 * std::abs(want)) << "system " << c.system << " at s = " << s;
    }
  }
}

TEST(ChatterStructure, StaticComplianceIsTheTwoSpringsInSeries) {
  const TwoMassStructure p{2.0, 5.0, 3e5, 0.5, 1.0, 2e5};
  EXPECT_NEAR(process::workpiece_compliance(p).at(0.0).real(), 1.0 / 3e5 + 1.0 / 2e5, 1e-18);
}

TEST(ChatterStructure, RigidMachineLeavesTheWorkpiece) {
  // Eq. 2.6: K_m >> K_w gives 1 / (M_w s^2 + C_w s + K_w); what is left of the machine (K_w / K_m = 1e-9) is
  // amplified near the lightly damped resonance by K_w / |dynamic stiffness| (about 1000 at 365 rad/s)
  const TwoMassStructure p{0.03, 0.1, 1.2e13, 0.09, 0.01, 12000.0};
  const process::TransferFunction g = process::workpiece_compliance(p);
  for (double w : {0.0, 200.0, 365.0, 1000.0}) {
    const C s(0.0, w), want = 1.0 / (p.M_w * s * s + p.C_w * s + p.K_w);
    EXPECT_LT(std::abs(g(s) - want), 1e-5 * std::abs(want)) << w;
  }
}

TEST(ChatterStructure, StiffWorkpieceAddsItsMassToTheMachine) {
  // Eq. 2.7: K_w >> K_m gives 1 / ((M_w + M_m) s^2 + C_m s + K_m)
  const TwoMassStructure p{0.03, 0.1, 120000.0, 0.09, 0.01, 1.2e15};
  const process::TransferFunction g = process::workpiece_compliance(p);
  for (double w : {0.0, 300.0, 1000.0, 1500.0}) {
    const C s(0.0, w), want = 1.0 / ((p.M_w + p.M_m) * s * s + p.C_m * s + p.K_m);
    EXPECT_LT(std::abs(g(s) - want), 1e-6 * std::abs(want)) << w;
  }
}

TEST(ChatterStructure, UndampedModesMakeTheDynamicStiffnessSingular) {
  for (const DunckleyCase& c : kDunckleyCases) {
    const TwoMassStructure p = dunckley_structure(c);
    const auto w = process::undamped_frequencies(p);
    for (double wi : w) {
      const double k11 = p.K_m + p.K_w - p.M_m * wi * wi, k22 = p.K_w - p.M_w * wi * wi;
      const double det = k11 * k22 - p.K_w * p.K_w, scale = (p.K_m + p.K_w) * p.K_w;
      EXPECT_LT(std::abs(det), 1e-9 * scale) << "system " << c.system << " w = " << wi;
    }
    EXPECT_LT(w[0], w[1]);
    // the damped modes are these within the light damping
    const auto m = process::modes(process::workpiece_compliance(p));
    ASSERT_EQ(m.size(), 2u);
    EXPECT_NEAR(m[0].omega_n, w[0], 1e-3 * w[0]);
    EXPECT_NEAR(m[1].omega_n, w[1], 1e-3 * w[1]);
    EXPECT_GT(m[0].zeta, 0.0);
    EXPECT_LT(m[0].zeta, 1e-3);
  }
}

TEST(ChatterStructure, RegenerationIsOneMinusTheDelayedOverlap) {
  for (double mu : {0.0, 0.4, 1.0})
    for (double w : {0.0, 1.0, 31.4159, 777.0}) {
      const C want = 1.0 - mu * std::exp(C(0.0, -w * 0.2));
      EXPECT_LT(std::abs(process::regeneration(mu, 0.2, w) - want), 1e-14);
    }
}

TEST(ChatterStructure, CheckNamesTheKey) {
  process::Cut cut;
  cut.revolution_period = 0.2;
  auto place = [&](TwoMassStructure p, process::Cut c) {
    try {
      process::check(p, c);
    } catch (const InputError& e) {
      return e.place();
    }
    return std::string("accepted");
  };
  const TwoMassStructure good{0.03, 0.1, 120000.0, 0.09, 0.01, 12000.0};
  EXPECT_EQ(place(good, cut), "accepted");
  TwoMassStructure p = good;
  p.M_w = 0.0;
  EXPECT_EQ(place(p, cut), "structure.M_w");
  p = good;
  p.C_m = -1.0;
  EXPECT_EQ(place(p, cut), "structure.C_m");
  p = good;
  p.C_m = p.C_w = 0.0;
  EXPECT_EQ(place(p, cut), "structure.C_m");
  process::Cut c = cut;
  c.overlap = 1.5;
  EXPECT_EQ(place(good, c), "cut.overlap");
  c = cut;
  c.revolution_period = 0.0;
  EXPECT_EQ(place(good, c), "cut.revolution_period");
  c.revolution_period = 1e4;  // 1.7 million cycles of the upper mode per revolution: too long a search
  EXPECT_EQ(place(good, c), "cut.revolution_period");
  c.revolution_period = 400.0;  // 840 000: still analysed
  EXPECT_EQ(place(good, c), "accepted");
}

}  // namespace tu_process_test_structure
}  // namespace polarcam::test
