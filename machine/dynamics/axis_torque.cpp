#include "machine/dynamics/axis_torque.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace polarcam {
namespace {

double sgn(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

AxisDemand demand(double torque, double rate, const StepperMotor& motor, const char* axis) {
  AxisDemand d;
  d.torque = torque;
  d.step_rate = rate;
  try {
    d.pullout = motor.pullout_at_rate(rate);
  } catch (const OutsideCurveError& e) {
    throw OutsideCurveError(std::string(axis) + " motor: " + e.what());
  }
  d.ratio = d.pullout > 0.0 ? torque / d.pullout : std::numeric_limits<double>::infinity();
  return d;
}

}  // namespace

PointDynamics point_dynamics(const PathState& st, double s, const MachineModel& m, const Load& load, int side,
                             FrictionMode mode) {
  PointDynamics p;
  p.st = st;
  const Mechanics& k = m.mech;
  const double M = k.carriage_mass + load.added_mass;
  p.force = load.force(s, st.V);
  // the force the drives apply against the process
  const Vec2 D = st.T * p.force.tangential - st.N * (p.force.normal * side);
  const double F_cr = dot(D, st.e_r), F_cn = dot(D, st.e_theta);

  const double T_R = k.K2 * (M * st.a_cr + F_cr);

  const double rest = k.arm_inertia * st.theta_ddot + M * st.r * st.a_cn + st.r * F_cn;
  const double F = k.arm_friction_torque;
  double T_theta;
  // the arm turns when its speed is more than rounding of the tangential speed; where it does not, theta'' says
  // which way it is about to turn (a reversal or a start from rest)
  const bool turning = std::abs(st.r * st.theta_dot) > 1e-9 * st.V;
  const double a_n = st.V * st.V * st.kappa;
  const double accel_scale = std::sqrt(st.a_t * st.a_t + a_n * a_n) + st.V * st.V / st.r;
  const double dir = std::abs(st.r * st.theta_ddot) > 1e-9 * accel_scale ? sgn(st.theta_ddot) : 0.0;
  if (turning) {
    T_theta = k.K1 * (rest + F * sgn(st.theta_dot));
  } else if (dir != 0.0) {
    // before a reversal the arm still turns against theta'', after it (or when starting) with it
    T_theta = k.K1 * (rest + F * (mode == FrictionMode::reversal_before ? -dir : dir));
  } else {
    T_theta = k.K1 * sgn(rest) * std::max(std::abs(rest) - F, 0.0);  // held by static friction
  }

  const double rate_R = k.k_R * std::abs(st.r_dot) * m.radial.steps_per_rev;
  const double rate_theta = k.k_theta * std::abs(st.theta_dot) / (2.0 * std::numbers::pi) * m.angular.steps_per_rev;
  p.radial = demand(T_R, rate_R, m.radial, "radial");
  p.angular = demand(T_theta, rate_theta, m.angular, "angular");
  return p;
}

}  // namespace polarcam
