// Closed forms of the dynamics along a path (Ch. 5, 6): a circle about the pole, a radial line, the linear effect
// of the carriage mass, the quartic dependence on speed (Eq. 6.3, 6.4 as corrected in docs/dynamics.md), the
// node of the witch and the symmetry of the circle (Sec. 5.5.1), and the maxima against dense sampling.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/path.hpp"
#include "tests/dynamics_helpers.hpp"
#include "machine/dynamics/verdict.hpp"

namespace tu_machine_dynamics_test_dynamics_analytic {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {
constexpr double kPi = std::numbers::pi;

double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }
}  // namespace

TEST(DynamicsAnalytic, CircleAboutThePole) {
  // r constant: r' = r'' = theta'' = 0, theta' = V/R. Radial: the centripetal term only; angular: friction only.
  const double R = 0.15, V = 0.0152, m = 14.6;
  for (bool reverse : {false, true}) {
    Rig s(make_circle({0, 0}, R), Placement{}, V, inertial(m), 1, reverse);
    const TorqueAnalysis a = s.run();
    const Mechanics& k = s.machine.mech;
    const double T_R = -k.K2 * (k.carriage_mass + m) * V * V / R;
    const double T_th = (reverse ? -1.0 : 1.0) * k.K1 * k.arm_friction_torque;
    const double rate_th = k.k_theta * V / R / (2 * kPi) * 400.0;
    const double Tp_th = s.machine.angular.pullout_at_rate(rate_th), Tp_R = s.machine.radial.pullout_at_rate(0.0);
    ASSERT_GT(a.series.size(), 1000u);
    for (const auto& x : a.series) {
      ASSERT_NEAR(x.radial.torque, T_R, 1e-12 * std::abs(T_R));
      ASSERT_NEAR(x.angular.torque, T_th, 1e-12 * std::abs(T_th));
      ASSERT_NEAR(x.radial.step_rate, 0.0, 1e-9);
      ASSERT_NEAR(x.angular.step_rate, rate_th, 1e-9 * rate_th);
      ASSERT_NEAR(x.radial.ratio, T_R / Tp_R, 1e-11 * std::abs(T_R / Tp_R));
      ASSERT_NEAR(x.angular.ratio, T_th / Tp_th, 1e-11 * std::abs(T_th / Tp_th));
    }
    EXPECT_NEAR(a.radial.ratio.value, std::abs(T_R / Tp_R), 1e-11);
    EXPECT_NEAR(a.angular.torque.value, std::abs(T_th), 1e-14);
    EXPECT_NEAR(a.total_torque.value, std::abs(T_R) + std::abs(T_th), 1e-14);
  }
}

TEST(DynamicsAnalytic, RadialLineNeedsNoAngularTorque) {
  // a line through the pole direction: theta constant, the arm never turns, friction holds it
  const double dir = 0.7;
  const Vec2 u{std::cos(dir), std::sin(dir)};
  for (bool with_force : {false, true}) {
    LoadSpec spec;
    spec.kind = with_force ? LoadKind::force : LoadKind::inertial;
    spec.mass = 10.0;
    spec.force.tangential = with_force ? 20.0 : 0.0;
    Rig s(make_line(u * 0.1, u * 0.3), Placement{}, 0.0152, make_load(spec));
    const TorqueAnalysis a = s.run();
    const double T_R = s.machine.mech.K2 * spec.force.tangential;  // the screw pushes against the feed force
    for (const auto& x : a.series) {
      ASSERT_EQ(x.angular.torque, 0.0);
      ASSERT_LT(x.angular.step_rate, 1e-9);  // theta' is zero to rounding
      ASSERT_NEAR(x.radial.torque, T_R, 1e-12 * std::max(T_R, 1e-12));
    }
    EXPECT_EQ(a.angular.ratio.value, 0.0);
  }
  // with a ramp the carriage's acceleration appears on the radial axis: T_R = K2 M a_t, still nothing angular
  Rig s(make_line(u * 0.1, u * 0.3), Placement{}, 0.0152, inertial(10.0));
  const double acc = 0.01;
  s.profile = make_trapezoid_speed(0.0152, acc, s.track.length());
  const TorqueAnalysis a = s.run();
  const double M = s.machine.mech.carriage_mass + 10.0;
  for (const auto& x : a.series) {
    ASSERT_EQ(x.angular.torque, 0.0);
    ASSERT_NEAR(std::abs(x.radial.torque), x.st.a_t == 0.0 ? 0.0 : s.machine.mech.K2 * M * acc, 1e-15);
  }
  EXPECT_NEAR(a.radial.torque.value, s.machine.mech.K2 * M * acc, 1e-15);
}

TEST(DynamicsAnalytic, InertialRatiosScaleLinearlyWithMass) {
  // Eq. 6.1, 6.2: the radial ratio is proportional to M_c + m, the angular one affine in it
  std::vector<TorqueAnalysis> runs;
  const double masses[] = {0.0, 14.6, 29.2, 43.8};
  for (double m : masses) runs.push_back(Rig(ch5_witch(), ch5_witch_pole(), 0.0151, inertial(m)).run());
  const double Mc = thesis_machine().mech.carriage_mass;
  for (size_t k = 1; k < 4; ++k) ASSERT_EQ(runs[k].series.size(), runs[0].series.size());
  for (size_t i = 0; i < runs[0].series.size(); ++i) {
    const auto r0 = runs[0].series[i].radial.ratio;
    for (size_t k = 1; k < 4; ++k)
      ASSERT_NEAR(runs[k].series[i].radial.ratio, r0 * (Mc + masses[k]) / Mc, 1e-12 + 1e-9 * std::abs(r0));
    const double a1 = runs[1].series[i].angular.ratio, a2 = runs[2].series[i].angular.ratio,
                 a3 = runs[3].series[i].angular.ratio;
    ASSERT_NEAR(a2 - a1, a3 - a2, 1e-12);
  }
  // and the maxima follow: max |ratio_R| scales with M
  EXPECT_NEAR(runs[3].radial.ratio.value / runs[1].radial.ratio.value, (Mc + 43.8) / (Mc + 14.6), 1e-9);
}

TEST(DynamicsAnalytic, RatioIsTheQuarticOfChapter6) {
  // At a fixed point the torque ratio is a ratio of a quartic in V to [L10^2 + L11^2 V^2]^(1/2) - L12 V
  // (Eq. 6.3, 6.4, with the corrections of docs/dynamics.md); the same point at several speeds.
  const double m = 29.2;
  const MachineModel M = thesis_machine();
  const Mechanics& k = M.mech;
  const ElectricalMotor e = thesis_motor();
  const double c1 = 4 / kPi * std::sin(3 * kPi / 8), Ra = e.R_a, La = e.L_a, Ns = e.rotor_teeth;
  const double Mt = k.carriage_mass + m, F = k.arm_friction_torque;
  const double L10 = c1 * e.supply_voltage * e.K_T * Ra;
  std::vector<double> prev_r;
  for (double V : {0.005, 0.0101, 0.0152, 0.03, 0.06}) {
    Rig s(make_limacon(0.0508, 0.0762), Placement{0.1778, 0.75 * kPi}, V, inertial(m));
    for (double u : {0.3, 1.1, 2.0, 2.9, 3.3, 4.4, 5.9}) {
      const PointDynamics p = s.at(u);
      const PathState& st = p.st;
      const double r = st.r, g = st.gamma, kap = st.kappa, sg = std::sin(g), cg = std::cos(g);
      // radial, Eq. 6.3: a_cr = -V^2 kappa sin(gamma) (the thesis's rho is positive turning right)
      const double L8 = -Mt * k.K2 * Ra * Ra * kap * sg;
      const double cR = 2 * kPi * Ns * k.k_R * La * std::abs(cg);
      const double L9 = L8 * cR * cR / (Ra * Ra);
      const double L11 = L10 * cR / Ra, L12 = e.K_V * 2 * kPi * Ra * e.K_T * k.k_R * std::abs(cg);
      const double ratio_R = (L8 * V * V + L9 * std::pow(V, 4)) / (std::sqrt(L10 * L10 + L11 * L11 * V * V) - L12 * V);
      EXPECT_LT(rel(p.radial.ratio, ratio_R), 1e-12) << "V " << V << " u " << u;
      // angular, Eq. 6.4: theta'' = V^2 (kappa cos g / r - sin 2g / r^2), a_cn = V^2 kappa cos g; omega = N_s k_theta
      // theta'
      const double X = k.arm_inertia * (kap * cg / r - std::sin(2 * g) / (r * r)) + Mt * r * kap * cg;
      const double sgn = sg > 0 ? 1.0 : -1.0;
      const double cT = Ns * k.k_theta * La * std::abs(sg) / r;
      const double L14 = Ra * Ra * k.K1 * F * sgn;
      const double L15 = Ra * Ra * k.K1 * X + k.K1 * F * sgn * cT * cT;
      const double L16 = k.K1 * X * cT * cT;
      const double L17 = L10 * cT / Ra, L18 = e.K_V * Ra * e.K_T * k.k_theta * std::abs(sg) / r;
      const double ratio_T =
          (L14 + L15 * V * V + L16 * std::pow(V, 4)) / (std::sqrt(L10 * L10 + L17 * L17 * V * V) - L18 * V);
      EXPECT_LT(rel(p.angular.ratio, ratio_T), 1e-12) << "V " << V << " u " << u;
    }
    // Sec. 6.5.1: the radial ratio always increases with V (inertial load)
    const TorqueAnalysis a = s.run();
    prev_r.push_back(a.radial.ratio.value);
  }
  for (size_t i = 1; i < prev_r.size(); ++i) EXPECT_GT(prev_r[i], prev_r[i - 1]);
}

TEST(DynamicsAnalytic, WitchAngularNodeAtHalfPi) {
  // Sec. 5.5.1 (b): at theta = pi/2 (x = 0) r' = 0 and theta'' = 0, so the inertial torque on the arm vanishes and
  // the angular ratio is the friction's, whatever the mass
  std::vector<double> ratios;
  for (double m : {14.6, 29.2, 43.8}) {
    Rig s(ch5_witch(), ch5_witch_pole(), 0.0151, inertial(m));
    const PointDynamics p = s.at(0.0);
    EXPECT_NEAR(std::atan2(p.st.q.y, p.st.q.x), kPi / 2, 1e-15);
    const Mechanics& k = s.machine.mech;
    EXPECT_NEAR(std::abs(p.angular.torque), k.K1 * k.arm_friction_torque, 1e-15);
    ratios.push_back(p.angular.ratio);
  }
  EXPECT_EQ(ratios[0], ratios[1]);
  EXPECT_EQ(ratios[1], ratios[2]);
}

TEST(DynamicsAnalytic, CircleRadialRatioSymmetricWithZerosAtTheArmsExtremes) {
  // Sec. 5.5.1 (a): the circle of Fig. 5.4 (centre straight above the pole): radial ratio symmetric about
  // theta = pi/2, zero where the arm reverses (theta = 1.318 and 1.823 rad)
  Rig s(ch5_circle(), ch5_circle_pole(), 0.0151, inertial(29.2));
  for (double u = 0.05; u < 2 * kPi; u += 0.1) {
    const PointDynamics a = s.at(u), b = s.at(kPi - u);  // mirror images in the line theta = pi/2
    EXPECT_NEAR(a.radial.ratio, b.radial.ratio, 1e-12 * std::abs(a.radial.ratio) + 1e-18) << u;
  }
  const TorqueAnalysis an = s.run();
  const double th_ext = std::asin(0.0508 / 0.2032);
  int zeros = 0;
  for (const auto& x : an.series)
    if (std::abs(x.st.theta_dot) < 1e-12) {  // the arm's reversals: samples placed exactly there
      EXPECT_NEAR(std::abs(x.theta - kPi / 2), th_ext, 1e-9);
      EXPECT_LT(std::abs(x.radial.ratio), 1e-12);
      ++zeros;
    }
  EXPECT_GE(zeros, 4);  // two reversals, each as the limits before and after
  // and the Coulomb jump of the angular torque there: 2 K1 F_f L_A between the two limits
  for (size_t i = 1; i < an.series.size(); ++i)
    if (an.series[i].s == an.series[i - 1].s && std::abs(an.series[i].st.theta_dot) < 1e-12) {
      EXPECT_NEAR(std::abs(an.series[i].angular.torque - an.series[i - 1].angular.torque),
                  2 * s.machine.mech.K1 * s.machine.mech.arm_friction_torque, 1e-12);
    }
}

TEST(DynamicsAnalytic, MaximaAreRefinedBeyondTheSampling) {
  // a coarse analysis finds the same maxima as a dense one
  Rig s(make_serpentine(0.0127, 0.0762, -0.0762, 0.0762), Placement{0.1778, 0.75 * kPi}, 0.0152, grinding());
  AnalysisOptions coarse;
  coarse.target_samples = 50;
  coarse.min_per_segment = 4;
  coarse.keep_series = false;
  AnalysisOptions dense;
  dense.target_samples = 200000;
  const TorqueAnalysis a = s.run(coarse), b = s.run(dense);
  for (auto [x, y] : {std::pair{a.radial.ratio.value, b.radial.ratio.value},
                      {a.angular.ratio.value, b.angular.ratio.value},
                      {a.radial.torque.value, b.radial.torque.value},
                      {a.angular.step_rate.value, b.angular.step_rate.value},
                      {a.total_torque.value, b.total_torque.value}})
    EXPECT_LT(rel(x, y), 1e-7) << x << " " << y;
  // every dense sample is at most the refined maximum
  for (const auto& x : b.series) ASSERT_LE(std::abs(x.radial.ratio), a.radial.ratio.value * (1 + 1e-9));
  // the count of samples does not depend on whether the series is kept: a segment's start that repeats the
  // previous end is one sample either way
  AnalysisOptions kept = coarse;
  kept.keep_series = true;
  const TorqueAnalysis c = s.run(kept);
  EXPECT_EQ(c.samples, c.series.size());
  EXPECT_EQ(a.samples, c.samples);
}

TEST(DynamicsAnalytic, GrindingExceedsOneAtTheHigherSpeed) {
  // Sec. 5.5.2: at 1.52 cm/s the radial ratio exceeds 1 for the circle and the witch; at 0.51 cm/s it does not
  for (int c = 0; c < 2; ++c) {
    for (double V : {0.0051, 0.0152}) {
      Rig s(c == 0 ? ch5_circle() : ch5_witch(), c == 0 ? ch5_circle_pole() : ch5_witch_pole(), V, grinding());
      const TorqueAnalysis a = s.run();
      if (V > 0.01)
        EXPECT_GT(a.radial.ratio.value, 1.0) << c;
      else
        EXPECT_LT(a.radial.ratio.value, 1.0) << c;
      const Verdict v = judge(a, s.machine, 1.0);
      EXPECT_EQ(v.go, V < 0.01);
      if (!v.go) {
        EXPECT_EQ(v.axis, 0);
      }
    }
  }
}

TEST(DynamicsAnalytic, NoPulloutLeftIsNoGo) {
  // a motor whose back-emf term exceeds its drive term above some rate has no pull-out torque there (Eq. 5.17
  // becomes negative): the ratio is infinite and the verdict names it
  MachineModel m = thesis_machine();
  ElectricalMotor e = thesis_motor();
  e.K_V = 20.0;  // V s/rad: T_p(w) < 0 once K_V w R_a / N_s > c1 V Z
  m.angular = make_electrical_motor(e);
  EXPECT_LT(e.pullout_at_rate(200.0), 0.0);
  Rig s(ch5_circle(), ch5_circle_pole(), 0.0152, inertial(14.6));
  s.machine = m;
  const TorqueAnalysis a = s.run();
  EXPECT_TRUE(std::isinf(a.angular.ratio.value));
  const Verdict v = judge(a, s.machine, 1.0);
  EXPECT_FALSE(v.go);
  EXPECT_EQ(v.axis, 1);
  EXPECT_EQ(v.failure, Failure::no_pullout);
  EXPECT_LT(v.where.angular.pullout, 0.0);
}

TEST(DynamicsAnalytic, PassingSpeedSearch) {
  // a predicate failing above f* = 0.6180...: found to the tolerance, always on the passing side
  const double fstar = 0.6180339887;
  SpeedSearch s = max_passing_speed_factor([&](double f) { return f <= fstar; });
  ASSERT_TRUE(s.factor);
  EXPECT_LE(*s.factor, fstar);
  EXPECT_GT(*s.factor, fstar * (1 - 2e-4));
  s = max_passing_speed_factor([&](double f) { return f <= 3.3; });
  ASSERT_TRUE(s.factor);
  EXPECT_NEAR(*s.factor, 3.3, 3.3 * 2e-4);
  EXPECT_FALSE(s.capped);
  s = max_passing_speed_factor([](double) { return true; });
  EXPECT_TRUE(s.capped);
  s = max_passing_speed_factor([](double) { return false; });
  EXPECT_FALSE(s.factor);
}

TEST(DynamicsAnalytic, PassingSpeedSearchConfirmedByTheExactTest) {
  // the exact test passes up to 2; a quick test that agrees, one that passes too much and one that passes too
  // little: the answer always passes the exact test and lies within the tolerance of 2
  const double limit = 2.0, tol = 1e-4;
  int exact_calls = 0;
  auto exact = [&](double f) {
    ++exact_calls;
    return f <= limit;
  };
  for (const double quick_limit : {2.0, 2.1, 1.9}) {
    SCOPED_TRACE(quick_limit);
    exact_calls = 0;
    int quick_calls = 0;
    const SpeedSearch s = max_passing_speed_factor(
        [&](double f) {
          ++quick_calls;
          return f <= quick_limit;
        },
        exact, 1e-3, 100.0, tol);
    ASSERT_TRUE(s.factor);
    EXPECT_LE(*s.factor, limit);
    EXPECT_GT(*s.factor, limit * (1 - 2 * tol));
    EXPECT_EQ(s.evaluations, quick_calls + exact_calls);
    if (quick_limit == limit)
      EXPECT_EQ(exact_calls, 2);  // the answer passes, the value two tolerances above fails: no second search
    else
      EXPECT_GT(exact_calls, 10);  // refused (it fails, or a larger value passes): searched again
  }
  // capped by the quick test and passing the exact one at the cap: one check
  exact_calls = 0;
  const SpeedSearch c = max_passing_speed_factor([](double) { return true; }, exact, 1e-3, 1.5, tol);
  EXPECT_TRUE(c.capped);
  EXPECT_EQ(exact_calls, 1);
}

TEST(DynamicsAnalytic, CornersAreReported) {
  // two lines meeting at a right angle: at the corner r' jumps from V cos(g1) to V cos(g2), theta' likewise
  const Vec2 a{0.10, 0.05}, b{0.20, 0.05}, c{0.20, 0.15};
  std::vector<PathSegment> segs{{PathSegment::Kind::line, a, b, {}, 0.0}, {PathSegment::Kind::line, b, c, {}, 0.0}};
  const double V = 0.0152;
  Rig s(make_path(segs, false), Placement{}, V, inertial(0.0));
  const TorqueAnalysis an = s.run();
  ASSERT_EQ(an.corners.size(), 1u);
  const Corner& k = an.corners[0];
  EXPECT_NEAR(k.turn, kPi / 2, 1e-12);
  EXPECT_NEAR(k.r, norm(b), 1e-12);
  EXPECT_NEAR(k.s, 0.1, 1e-12);
  const Vec2 er = b / norm(b), et = perp(er);
  const Mechanics& m = s.machine.mech;
  // before: travel along +x; after: along +y
  const double rd0 = V * er.x, rd1 = V * er.y, td0 = V * et.x / norm(b), td1 = V * et.y / norm(b);
  EXPECT_NEAR(k.radial_rate_jump, m.k_R * std::abs(rd1 - rd0) * 400, 1e-9);
  EXPECT_NEAR(k.angular_rate_jump, m.k_theta * std::abs(td1 - td0) / (2 * kPi) * 400, 1e-9);
  // a smooth closed curve has none
  EXPECT_TRUE(Rig(ch5_circle(), ch5_circle_pole(), V, inertial(0.0)).run().corners.empty());
}

TEST(DynamicsAnalytic, ToolRadiusMovesTheCarriageOnTheOffsetPath) {
  // a circle of radius R about the pole cut with a tool of radius R_r outside it: the carriage runs on the circle
  // of radius R + R_r (at the job's speed, the tool centre's), so T_R = -K2 M V^2 / (R + R_r)
  const double R = 0.15, Rr = 0.01, V = 0.0152, m = 14.6;
  const MachineModel M = thesis_machine();
  const Load load = inertial(m);
  auto path = make_tool_path(make_circle({0, 0}, R), Placement{}, ToolSpec{Rr, ToolSide::outside}, TravelSpec{});
  const PolarTrack track = PolarTrack::build(*path);
  auto prof = make_constant_speed(V, track.length());
  const TorqueAnalysis a = analyze_torques({path.get(), &track, 0.0, prof.get(), &M, &load, 1});
  const double T_R = -M.mech.K2 * (M.mech.carriage_mass + m) * V * V / (R + Rr);
  for (const auto& x : a.series) {
    ASSERT_NEAR(x.r, R + Rr, 1e-12);
    ASSERT_NEAR(x.radial.torque, T_R, 1e-10 * std::abs(T_R));
  }
}

}  // namespace tu_machine_dynamics_test_dynamics_analytic
