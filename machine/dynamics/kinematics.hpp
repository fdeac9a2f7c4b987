#pragma once
// Kinematics of the arm and carriage at one point of the tool-centre path (Eq. 5.1-5.8 of
// A. Fahim's thesis (1983)), computed from the path geometry and the speed profile, in vector form:
//   velocity v = V T, acceleration a = a_t T + V^2 kappa N   (T unit tangent, N = T turned +90 deg, kappa signed
//   curvature, + when the path turns left; a_t = dV/dt, zero at the thesis's constant speed),
//   r' = v.e_r = V cos gamma,  r theta' = v.e_theta = V sin gamma               (Eq. 5.2, 5.3)
//   a_cr = a.e_r = r'' - r theta'^2,  a_cn = a.e_theta = r theta'' + 2 r' theta'   (Eq. 5.6, 5.7)
// gamma being the angle from the radius vector e_r to the tangent T, counter-clockwise.
#include "cam/curve.hpp"

namespace polarcam {

struct PathState {
  Vec2 q;                                 // m, tool centre about the machine pole
  double r = 0.0;                         // m
  double V = 0.0;                         // m/s, tangential speed
  double a_t = 0.0;                       // m/s^2, tangential acceleration
  double kappa = 0.0;                     // 1/m, signed curvature of the path
  Vec2 T, N;                              // unit tangent (direction of travel) and left normal
  Vec2 e_r, e_theta;                      // unit radial and angular directions
  double gamma = 0.0;                     // rad in [0, 2 pi): angle from e_r to T
  double r_dot = 0.0, theta_dot = 0.0;    // m/s, rad/s
  double r_ddot = 0.0, theta_ddot = 0.0;  // m/s^2, rad/s^2
  double a_cr = 0.0, a_cn = 0.0;          // m/s^2, acceleration along and across the arm
};

// From the path point and its first two derivatives with respect to the path parameter (origin at the machine
// pole), the speed V and tangential acceleration a_t there. The point must not be the pole and Q' must not
// vanish. `with_gamma` false leaves gamma at 0 (an atan2 the torque analysis needs only at the ends of its segments).
PathState path_state(const CurvePoint& q, double V, double a_t, bool with_gamma = true);

}  // namespace polarcam
