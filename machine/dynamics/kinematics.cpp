#include "machine/dynamics/kinematics.hpp"

#include <cmath>
#include <numbers>

namespace polarcam {

PathState path_state(const CurvePoint& q, double V, double a_t, bool with_gamma) {
  PathState st;
  st.q = q.p;
  // sqrt rather than hypot: the path's coordinates and derivatives are far from overflow or underflow
  st.r = std::sqrt(dot(q.p, q.p));
  st.V = V;
  st.a_t = a_t;
  const double sp = std::sqrt(dot(q.d1, q.d1));
  st.T = q.d1 / sp;
  st.N = perp(st.T);
  st.kappa = cross(q.d1, q.d2) / (sp * sp * sp);
  st.e_r = q.p / st.r;
  st.e_theta = perp(st.e_r);
  if (with_gamma) {
    const double cg = dot(st.T, st.e_r), sg = dot(st.T, st.e_theta);
    st.gamma = std::atan2(sg, cg);
    if (st.gamma < 0.0) st.gamma += 2.0 * std::numbers::pi;
  }
  const Vec2 v = st.T * V;
  const Vec2 a = st.T * a_t + st.N * (V * V * st.kappa);
  st.r_dot = dot(v, st.e_r);
  st.theta_dot = dot(v, st.e_theta) / st.r;
  st.a_cr = dot(a, st.e_r);
  st.a_cn = dot(a, st.e_theta);
  st.r_ddot = st.a_cr + st.r * st.theta_dot * st.theta_dot;
  st.theta_ddot = (st.a_cn - 2.0 * st.r_dot * st.theta_dot) / st.r;
  return st;
}

}  // namespace polarcam
