// The dynamics of a seed contour against an independent computation: the limacon of Fig. 5.6 at its Ch. 5 pole,
// ground with an added mass, evaluated in long double from the thesis's polar forms (curvature of r1(theta1),
// tangent angle, Eq. 5.2-5.8, 5.15-5.21 with the units of Eq. 5.18-5.19 sorted out) with the parameters read from
// the shared reference data (Table 5.1; tests/data holds a copy).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/curves.hpp"
#include "tests/dynamics_helpers.hpp"
#include "tests/reference_data.hpp"

namespace tu_machine_dynamics_test_dynamics_reference {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

using polarcam::test::read_reference;
using polarcam::test::Reference;

using LD = long double;
const LD kPiL = 3.141592653589793238462643383279502884L;

// Everything at theta1 on the limacon r1 = b + a cos(theta1), pole O = O1 + C e^{j beta}, constant speed V.
struct Expected {
  LD r, theta_dot, T_R, T_theta, Tp_R, Tp_theta;
};
Expected independent(const Reference& p, LD a, LD b, LD C, LD beta, LD V, LD mass, int side, LD th1) {
  const LD r1 = b + a * std::cos(th1), d1 = -a * std::sin(th1), d2 = -a * std::cos(th1);
  const LD x = r1 * std::cos(th1) - C * std::cos(beta), y = r1 * std::sin(th1) - C * std::sin(beta);
  const LD r = std::hypot(x, y), theta = std::atan2(y, x);
  const LD phi = th1 + std::atan2(r1, d1);  // direction of the tangent (increasing theta1)
  const LD kappa = (r1 * r1 + 2 * d1 * d1 - r1 * d2) / std::pow(r1 * r1 + d1 * d1, 1.5L);
  const LD g = phi - theta, sg = std::sin(g), cg = std::cos(g);
  const LD rd = V * cg, thd = V * sg / r;                          // Eq. 5.2, 5.3
  const LD a_cr = -V * V * kappa * sg, a_cn = V * V * kappa * cg;  // Eq. 5.6-5.8
  const LD thdd = (a_cn - 2 * rd * thd) / r;
  const LD alpha = std::atan((LD)p.c1);  // Eq. 5.22, 5.23
  const LD Kc = (LD)p.k_c * std::sqrt(1 + (LD)p.c1 * p.c1) * p.depth * p.width / p.V_tool;
  const LD Ft = Kc * V * std::cos(alpha), Fn = Kc * V * std::sin(alpha);
  const LD F_cr = Ft * cg + side * Fn * sg, F_cn = Ft * sg - side * Fn * cg;
  const LD M = p.M_c + mass;
  Expected e;
  e.r = r;
  e.theta_dot = thd;
  e.T_R = p.K2 * (M * a_cr + F_cr);                                                           // Eq. 5.15
  e.T_theta = p.K1 * (p.J_A * thdd + M * r * a_cn + r * F_cn + p.FfLA * (thd > 0 ? 1 : -1));  // Eq. 5.16
  auto pullout = [&](LD w) {                                                                  // Eq. 5.17
    const LD z2 = (LD)p.R_a * p.R_a + w * w * p.L_a * p.L_a;
    const LD c = 4 / kPiL * std::sin(3 * kPiL / 8);  // = the printed 1.17632
    return c * p.V_supply * p.K_T / std::sqrt(z2) - (LD)p.K_V * w * p.R_a * p.K_T / (p.N_s * z2);
  };
  e.Tp_R = pullout(2 * kPiL * p.N_s * p.k_R * std::fabs(rd));  // Eq. 5.18: k_R r' in rev/s
  e.Tp_theta = pullout(p.N_s * p.k_theta * std::fabs(thd));    // Eq. 5.19 with theta' in rad/s: no 2 pi
  return e;
}

}  // namespace

TEST(DynamicsReference, LimaconAgainstIndependentPolarForms) {
  auto ref = read_reference();
  if (!ref) GTEST_SKIP() << "shared reference data not found at " << POLARCAM_SHARED_DIR;
  const Reference& p = *ref;
  EXPECT_NEAR(p.c_pullout, 4 / std::numbers::pi * std::sin(3 * std::numbers::pi / 8), 0.5e-5);

  MachineModel m;
  m.mech = {p.M_c, p.J_A, p.FfLA, p.K1, p.K2, p.k_theta, p.k_R};
  ElectricalMotor e{p.V_supply, p.K_T, p.K_V, p.N_s, p.R_a, p.L_a, Energisation::wave};
  m.radial = m.angular = make_electrical_motor(e);
  LoadSpec ls;
  ls.kind = LoadKind::grinding;
  ls.mass = 14.6;
  ls.grinding = {p.k_c, p.c1, p.depth, p.width, p.V_tool};
  const Load load = make_load(ls);
  const double a = 0.0508, b = 0.0762, C = 0.1778, beta = 0.75 * std::numbers::pi, V = 0.0152;
  for (int side : {1, -1}) {
    auto path = make_tool_path(make_limacon(a, b), Placement{C, beta}, ToolSpec{}, TravelSpec{});
    const PolarTrack track = PolarTrack::build(*path);
    auto prof = make_constant_speed(V, track.length());
    DynamicsInput in{path.get(), &track, 0.0, prof.get(), &m, &load, side};
    const TorqueAnalysis an = analyze_torques(in);
    double scale_R = 0, scale_T = 0;
    for (const auto& x : an.series) {
      scale_R = std::max(scale_R, std::abs(x.radial.torque));
      scale_T = std::max(scale_T, std::abs(x.angular.torque));
    }
    size_t compared = 0;
    for (const auto& x : an.series) {
      const Expected ex = independent(p, a, b, C, beta, V, 14.6, side, x.u);
      ASSERT_NEAR(x.r, (double)ex.r, 1e-12 * x.r);
      if (std::fabs(ex.theta_dot) * ex.r < 1e-9 * V) continue;  // the arm's reversals: friction takes a side there
      auto check = [&](double got, LD want, double scale, const char* what) {
        EXPECT_LE(std::abs(got - (double)want), 1e-6 * std::fabs((double)want) + 1e-12 * scale)
            << what << " at theta1 = " << x.u << ": " << got << " vs " << (double)want;
      };
      check(x.radial.torque, ex.T_R, scale_R, "T_R");
      check(x.angular.torque, ex.T_theta, scale_T, "T_theta");
      check(x.radial.pullout, ex.Tp_R, 0.0, "T_pR");
      check(x.angular.pullout, ex.Tp_theta, 0.0, "T_ptheta");
      check(x.radial.ratio, ex.T_R / ex.Tp_R, 0.0, "ratio R");
      check(x.angular.ratio, ex.T_theta / ex.Tp_theta, 0.0, "ratio theta");
      ++compared;
    }
    EXPECT_GT(compared, 3000u);
  }
}

}  // namespace tu_machine_dynamics_test_dynamics_reference
