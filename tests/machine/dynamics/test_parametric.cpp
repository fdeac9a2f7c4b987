// The closed forms of the parametric study of Ch. 6 (machine/dynamics/parametric.hpp, docs/optimum-loading.md) against the
// numerical dynamics (machine/axis_torque: point_dynamics on a path state): the quartic torque-ratio forms and their
// sensitivities at points of every orientation and curvature, and the locations of the largest torques (gamma_R =
// pi/2, Eq. 6.15, 6.19, 6.20) against a dense sweep of the tangent's direction at a point.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "cam/error.hpp"
#include "tests/dynamics_helpers.hpp"
#include "machine/dynamics/axis_torque.hpp"
#include "machine/dynamics/kinematics.hpp"
#include "machine/dynamics/parametric.hpp"

namespace tu_machine_dynamics_test_parametric {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {
constexpr double kPi = std::numbers::pi;

double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

// A point at distance r from the machine pole (polar angle phi) whose unit tangent makes gamma with the radius
// vector, on a path of curvature kappa (+ turning left), traversed at V.
PathState point(double r, double phi, double gamma, double kappa, double V) {
  CurvePoint q;
  q.p = Vec2{r * std::cos(phi), r * std::sin(phi)};
  const Vec2 T{std::cos(phi + gamma), std::sin(phi + gamma)};
  q.d1 = T;
  q.d2 = perp(T) * kappa;
  return path_state(q, V, 0.0);
}

PointDynamics dyn(const MachineModel& m, const Load& l, int side, double r, double g, double kap, double V) {
  return point_dynamics(point(r, 0.4, g, kap, V), 0.0, m, l, side, FrictionMode::moving);
}

ParametricLoad grinding_params(const GrindingSpec& g, int side) {
  return ParametricLoad{0.0, g.K_c(), std::atan(g.c1), side};
}

// The distance between two angles modulo `period`.
double angle_dist(double a, double b, double period) {
  double d = std::fmod(std::abs(a - b), period);
  return std::min(d, period - d);
}

// argmax over gamma in [0, 2 pi) of |f(gamma)|: a dense sweep, then golden-section refinement of the best bracket.
double argmax_abs(const std::function<double(double)>& f) {
  const int n = 7200;
  int best = 0;
  double bv = -1.0;
  for (int i = 0; i < n; ++i) {
    const double v = std::abs(f(2 * kPi * i / n));
    if (v > bv) bv = v, best = i;
  }
  double a = 2 * kPi * (best - 1) / n, b = 2 * kPi * (best + 1) / n;
  const double gr = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 80; ++it) {
    const double c = b - gr * (b - a), d = a + gr * (b - a);
    if (std::abs(f(c)) > std::abs(f(d))) b = d; else a = c;
  }
  const double g = 0.5 * (a + b);
  return g < 0 ? g + 2 * kPi : (g >= 2 * kPi ? g - 2 * kPi : g);
}

struct Pt {
  double r, g, kappa;
};
// points of both turning senses, both signs of sin and cos gamma, near and far
const Pt kPoints[] = {{0.18, 0.7, 12.0},  {0.25, 2.2, -8.0}, {0.12, 4.0, 25.0},
                      {0.30, 5.5, -3.0},  {0.2, 1.5707, 19.7}, {0.15, 3.3, 0.0}};
}  // namespace

TEST(Parametric, InertialRatioFormsMatchTheNumericalDynamics) {
  const MachineModel m = thesis_machine();
  for (double mass : {0.0, 29.2}) {
    const Load l = inertial(mass);
    for (int side : {1, -1})
      for (const Pt& p : kPoints)
        for (double V : {0.004, 0.0152, 0.05}) {
          const PointDynamics d = dyn(m, l, side, p.r, p.g, p.kappa, V);
          const RatioForms f = ratio_forms(m, ContourPoint{p.r, d.st.gamma, d.st.kappa}, ParametricLoad{mass, 0, 0, side});
          EXPECT_LT(rel(f.radial.ratio(V), d.radial.ratio), 1e-10) << p.r << " " << p.g << " V " << V;
          EXPECT_LT(rel(f.angular.ratio(V), d.angular.ratio), 1e-10) << p.r << " " << p.g << " V " << V;
        }
  }
}

TEST(Parametric, GrindingRatioFormsMatchTheNumericalDynamics) {
  const MachineModel m = thesis_machine();
  const GrindingSpec gs = thesis_grinding();
  const Load l = grinding(gs);
  for (int side : {1, -1})
    for (const Pt& p : kPoints)
      for (double V : {0.004, 0.0102, 0.03}) {
        const PointDynamics d = dyn(m, l, side, p.r, p.g, p.kappa, V);
        const RatioForms f = ratio_forms(m, ContourPoint{p.r, d.st.gamma, d.st.kappa}, grinding_params(gs, side));
        EXPECT_LT(rel(f.radial.ratio(V), d.radial.ratio), 1e-9) << side << " " << p.g << " V " << V;
        EXPECT_LT(rel(f.angular.ratio(V), d.angular.ratio), 1e-9) << side << " " << p.g << " V " << V;
      }
}

TEST(Parametric, SensitivityIsTheDerivativeOfTheNumericalRatio) {
  // Gamma = d ratio / d V_t (Eq. 6.5, 6.6, 6.11, 6.12) against a central difference of the numerical dynamics
  const MachineModel m = thesis_machine();
  const GrindingSpec gs = thesis_grinding();
  for (bool grind : {false, true}) {
    const Load l = grind ? grinding(gs) : inertial(29.2);
    const ParametricLoad pl = grind ? grinding_params(gs, 1) : ParametricLoad{29.2, 0, 0, 1};
    for (const Pt& p : kPoints)
      for (double V : {0.006, 0.02}) {
        const double h = V * 1e-5;
        const PointDynamics d = dyn(m, l, 1, p.r, p.g, p.kappa, V);
        const RatioForms f = ratio_forms(m, ContourPoint{p.r, d.st.gamma, d.st.kappa}, pl);
        const double dR = (dyn(m, l, 1, p.r, p.g, p.kappa, V + h).radial.ratio -
                           dyn(m, l, 1, p.r, p.g, p.kappa, V - h).radial.ratio) / (2 * h);
        const double dT = (dyn(m, l, 1, p.r, p.g, p.kappa, V + h).angular.ratio -
                           dyn(m, l, 1, p.r, p.g, p.kappa, V - h).angular.ratio) / (2 * h);
        EXPECT_NEAR(f.radial.sensitivity(V), dR, 1e-6 * std::max(1.0, std::abs(dR))) << grind << " " << p.g;
        EXPECT_NEAR(f.angular.sensitivity(V), dT, 1e-6 * std::max(1.0, std::abs(dT))) << grind << " " << p.g;
      }
  }
}

// The speed-dependent part of a torque at a point as a function of the tangent's direction: T(V) - T(V -> 0)
// removes the arm's friction (constant for a given direction of turning).
std::function<double(double)> torque_part(const MachineModel& m, const Load& l, int side, double r, double kap,
                                          double V, bool radial) {
  return [&m, &l, side, r, kap, V, radial](double g) {
    const PointDynamics a = dyn(m, l, side, r, g, kap, V), b = dyn(m, l, side, r, g, kap, V * 1e-9);
    return radial ? a.radial.torque - b.radial.torque : a.angular.torque - b.angular.torque;
  };
}

TEST(Parametric, InertialMaximaLocations) {
  const MachineModel m = thesis_machine();
  for (double mass : {0.0, 14.6, 43.8}) {
    const Load l = inertial(mass);
    for (const Pt& p : {Pt{0.18, 0, 12.0}, Pt{0.25, 0, -8.0}, Pt{0.1, 0, 40.0}, Pt{0.3, 0, 2.0}}) {
      // radial: gamma_R = pi/2 (or its twin 3 pi/2)
      const double gR = argmax_abs(torque_part(m, l, 1, p.r, p.kappa, 0.0152, true));
      EXPECT_LT(angle_dist(gR, gamma_max_radial_inertial(), kPi), 1e-6) << mass << " " << p.kappa;
      // angular: Eq. 6.15 (as corrected)
      // angular: Eq. 6.15 (as corrected): the largest |torque| at a twin pair gamma, pi - gamma of opposite signs; the
      // one returned drives +theta
      const auto part = torque_part(m, l, 1, p.r, p.kappa, 0.0152, false);
      const double gT = argmax_abs(part);
      const double g615 = gamma_max_angular_inertial(m.mech, ContourPoint{p.r, 0.0, p.kappa}, mass);
      EXPECT_LT(std::min(angle_dist(gT, g615, 2 * kPi), angle_dist(gT, kPi - g615, 2 * kPi)), 1e-6)
          << mass << " " << p.r << " " << p.kappa;
      EXPECT_NEAR(std::abs(part(g615)), std::abs(part(gT)), 1e-9 * std::abs(part(gT)));
      EXPECT_GT(part(g615), 0.0);
    }
  }
}

TEST(Parametric, GrindingMaximaLocations) {
  const MachineModel m = thesis_machine();
  const GrindingSpec gs = thesis_grinding();
  const Load l = grinding(gs);
  for (int side : {1, -1})
    for (double V : {0.005, 0.0102, 0.03})
      for (const Pt& p : {Pt{0.18, 0, 12.0}, Pt{0.25, 0, -8.0}, Pt{0.1, 0, 40.0}}) {
        const ContourPoint cp{p.r, 0.0, p.kappa};
        const ParametricLoad pl = grinding_params(gs, side);
        // radial, Eq. 6.19: exact (the torque is a sinusoid in gamma, its twin at gamma + pi)
        const double gR = argmax_abs(torque_part(m, l, side, p.r, p.kappa, V, true));
        EXPECT_LT(angle_dist(gR, gamma_max_radial_grinding(m.mech, cp, pl, V), kPi), 1e-6) << side << " " << V;
        // angular, Eq. 6.20: neglects J_A V^2 sin(2 gamma) / r^2 against the force (a few 1e-4 rad here)
        const double gT = argmax_abs(torque_part(m, l, side, p.r, p.kappa, V, false));
        // the neglected term against the force's: J_A V^2 / r^2 : K_c V r bounds the shift
        const double neglect = m.mech.arm_inertia * V / (p.r * p.r * p.r * pl.K_c);
        EXPECT_LT(angle_dist(gT, gamma_max_angular_grinding(m.mech, cp, pl, V), kPi), 2 * neglect) << side << " " << V;
        EXPECT_GT(angle_dist(gT, gamma_max_angular_grinding(m.mech, cp, pl, V), kPi), 1e-3 * neglect);  // not exact
      }
}

TEST(Parametric, LocationDerivativesMatchDifferences) {
  // Eq. 6.16, 6.21-6.24 against central differences of the locations they differentiate
  const MachineModel m = thesis_machine();
  const GrindingSpec gs = thesis_grinding();
  const ContourPoint cp{0.2, 0.0, 10.0};
  const ParametricLoad pl = grinding_params(gs, 1);
  const double V = 0.0102, hV = 1e-7;
  auto near = [](double a, double b) { EXPECT_NEAR(a, b, 1e-5 * std::max(1e-3, std::abs(b))); };
  near(dgamma_radial_grinding_dV(m.mech, cp, pl, V),
       (gamma_max_radial_grinding(m.mech, cp, pl, V + hV) - gamma_max_radial_grinding(m.mech, cp, pl, V - hV)) / (2 * hV));
  near(dgamma_angular_grinding_dV(m.mech, cp, pl, V),
       (gamma_max_angular_grinding(m.mech, cp, pl, V + hV) - gamma_max_angular_grinding(m.mech, cp, pl, V - hV)) /
           (2 * hV));
  const double hK = pl.K_c * 1e-7;
  ParametricLoad up = pl, dn = pl;
  up.K_c += hK, dn.K_c -= hK;
  near(dgamma_radial_grinding_dKc(m.mech, cp, pl, V),
       (gamma_max_radial_grinding(m.mech, cp, up, V) - gamma_max_radial_grinding(m.mech, cp, dn, V)) / (2 * hK));
  near(dgamma_angular_grinding_dKc(m.mech, cp, pl, V),
       (gamma_max_angular_grinding(m.mech, cp, up, V) - gamma_max_angular_grinding(m.mech, cp, dn, V)) / (2 * hK));
  const double hM = 1e-4;
  near(dgamma_angular_inertial_dmass(m.mech, cp, 20.0),
       (gamma_max_angular_inertial(m.mech, cp, 20.0 + hM) - gamma_max_angular_inertial(m.mech, cp, 20.0 - hM)) /
           (2 * hM));
}

TEST(Parametric, RejectsWhatTheFormsCannotDescribe) {
  const MachineModel m = thesis_machine();
  EXPECT_THROW(ratio_forms(m, ContourPoint{0.2, 0.0, 1.0}, ParametricLoad{}), InputError);  // sin gamma = 0
  EXPECT_THROW(ratio_forms(m, ContourPoint{0.0, 1.0, 1.0}, ParametricLoad{}), InputError);  // at the pole
}

}  // namespace tu_machine_dynamics_test_parametric
