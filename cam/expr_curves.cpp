#include "cam/expr_curves.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/expression.hpp"

namespace polarcam {
namespace {

// Checks that f is finite on [a, b] (at 257 points) and returns the largest excess there (Expression::excess):
// the rounding scale of the numbers the curve's position is computed from, beyond the position.
double scan(const Expression& f, double a, double b, const std::string& var) {
  double most = 0.0;
  for (int i = 0; i <= 256; ++i) {
    double x = a + (b - a) * i / 256.0;
    double v = f(x);
    if (!std::isfinite(v)) {
      std::ostringstream os;
      os.precision(6);
      os << "'" << f.text() << "' is not finite at " << var << " = " << x;
      throw InputError(os.str(), f.key());
    }
    const double e = f.excess(x);
    if (std::isfinite(e)) most = std::max(most, e);
  }
  return most;
}

void require_range(double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b) || !(b > a))
    throw InputError("the parameter range is empty: the end must be greater than the start");
}

class PolarExpr final : public Curve {
 public:
  PolarExpr(Expression f, double t0, double t1, bool closed, double unit, double rounding)
      : Curve(t0, t1, closed, "polar r=" + f.text()), f_(std::move(f)), unit_(unit), rounding_(rounding) {}
  double rounding_scale() const override { return rounding_; }
  CurvePoint eval(double t, int order) const override {
    double r[4];
    f_.derivatives(t, order, r);
    return polar_point(t, unit_ * r[0], unit_ * r[1], unit_ * r[2], unit_ * r[3], order);
  }

 private:
  Expression f_;
  double unit_, rounding_;  // rounding_: metres
};

class CartesianExpr final : public Curve {
 public:
  CartesianExpr(Expression f, double x0, double x1, double unit, double rounding)
      : Curve(x0, x1, false, "cartesian y=" + f.text()), f_(std::move(f)), unit_(unit), rounding_(rounding) {}
  double rounding_scale() const override { return rounding_; }
  // u is x in the user's unit
  CurvePoint eval(double x, int order) const override {
    double y[4];
    f_.derivatives(x, order, y);
    CurvePoint p;
    p.p = Vec2{x, y[0]} * unit_;
    if (order >= 1) p.d1 = Vec2{1.0, y[1]} * unit_;
    if (order >= 2) p.d2 = Vec2{0.0, y[2]} * unit_;
    if (order >= 3) p.d3 = Vec2{0.0, y[3]} * unit_;
    return p;
  }

 private:
  Expression f_;
  double unit_, rounding_;  // rounding_: metres
};

class ParametricExpr final : public Curve {
 public:
  ParametricExpr(Expression fx, Expression fy, double u0, double u1, bool closed, double unit, double rounding)
      : Curve(u0, u1, closed, "parametric x=" + fx.text() + " y=" + fy.text()), fx_(std::move(fx)), fy_(std::move(fy)),
        unit_(unit), rounding_(rounding) {}
  double rounding_scale() const override { return rounding_; }
  CurvePoint eval(double u, int order) const override {
    double x[4], y[4];
    fx_.derivatives(u, order, x);
    fy_.derivatives(u, order, y);
    CurvePoint p;
    p.p = Vec2{x[0], y[0]} * unit_;
    p.d1 = Vec2{x[1], y[1]} * unit_;
    p.d2 = Vec2{x[2], y[2]} * unit_;
    p.d3 = Vec2{x[3], y[3]} * unit_;
    return p;
  }

 private:
  Expression fx_, fy_;
  double unit_, rounding_;  // rounding_: metres
};

void require_unit(double unit_m) {
  if (!(unit_m > 0.0) || !std::isfinite(unit_m)) throw InputError("the expression unit must be a positive length");
}

}  // namespace

CurvePtr make_polar_expr(const std::string& r_expr, double t_from, double t_to, bool closed, double unit_m,
                         const ExprConstants& constants) {
  require_range(t_from, t_to);
  require_unit(unit_m);
  Expression f(r_expr, {"t", "theta"}, constants, "r");
  const double e = scan(f, t_from, t_to, "t");
  return std::make_shared<PolarExpr>(std::move(f), t_from, t_to, closed, unit_m, e * unit_m);
}

CurvePtr make_cartesian_expr(const std::string& y_expr, double x_from_m, double x_to_m, double unit_m,
                             const ExprConstants& constants) {
  require_range(x_from_m, x_to_m);
  require_unit(unit_m);
  Expression f(y_expr, {"x"}, constants, "y");
  double a = x_from_m / unit_m, b = x_to_m / unit_m;
  const double e = scan(f, a, b, "x");
  return std::make_shared<CartesianExpr>(std::move(f), a, b, unit_m, e * unit_m);
}

CurvePtr make_parametric_expr(const std::string& x_expr, const std::string& y_expr, double u_from, double u_to,
                              bool closed, double unit_m, const ExprConstants& constants) {
  require_range(u_from, u_to);
  require_unit(unit_m);
  Expression fx(x_expr, {"u", "t"}, constants, "x");
  Expression fy(y_expr, {"u", "t"}, constants, "y");
  const double e = std::max(scan(fx, u_from, u_to, "u"), scan(fy, u_from, u_to, "u"));
  return std::make_shared<ParametricExpr>(std::move(fx), std::move(fy), u_from, u_to, closed, unit_m, e * unit_m);
}

}  // namespace polarcam
