#pragma once
// Curves typed by the user as expressions (muparser): polar r(t), explicit Cartesian y(x), parametric x(u), y(u).
// Expressions are evaluated in the user's length unit (`unit_m` metres per unit) and may use named constants.
// Derivatives are exact to rounding (automatic differentiation, cam/expression.hpp). Errors in an expression are
// InputErrors placed at its key (`r`, `y`, `x`), which the job reader turns into the job's key.
#include <map>
#include <string>

#include "cam/curve.hpp"

namespace polarcam {

using ExprConstants = std::map<std::string, double>;

// r = r_expr(t) (variables `t` and `theta`), t in [t_from, t_to].
CurvePtr make_polar_expr(const std::string& r_expr, double t_from, double t_to, bool closed, double unit_m,
                         const ExprConstants& constants);

// y = y_expr(x) with x in [x_from, x_to] (metres); x and y in the user's unit inside the expression.
CurvePtr make_cartesian_expr(const std::string& y_expr, double x_from_m, double x_to_m, double unit_m,
                             const ExprConstants& constants);

// x = x_expr(u), y = y_expr(u) (variables `u` and `t`), u in [u_from, u_to].
CurvePtr make_parametric_expr(const std::string& x_expr, const std::string& y_expr, double u_from, double u_to,
                              bool closed, double unit_m, const ExprConstants& constants);

}  // namespace polarcam
