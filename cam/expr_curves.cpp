#include "cam/expr_curves.hpp"

#include <muParser.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <numbers>
#include <unordered_map>

#include "cam/curves.hpp"
#include "cam/error.hpp"

namespace polarcam {
namespace {

// One scalar expression of one variable. muparser instances are not thread-safe, so each thread compiles its own
// copy on first use (keyed by a unique id, never by address).
class ExprFunction {
 public:
  ExprFunction(std::string expr, std::vector<std::string> var_names, ExprConstants constants, std::string what)
      : expr_(std::move(expr)), vars_(std::move(var_names)), consts_(std::move(constants)), what_(std::move(what)),
        id_(next_id()) {
    compile();  // reports syntax errors at construction
  }

  double operator()(double x) const {
    Compiled& c = local();
    c.var = x;
    try {
      return c.parser.Eval();
    } catch (mu::Parser::exception_type& e) {
      throw InputError(what_ + " '" + expr_ + "': " + e.GetMsg());
    }
  }

  const std::string& text() const { return expr_; }

 private:
  struct Compiled {
    mu::Parser parser;
    double var = 0.0;
  };

  static uint64_t next_id() {
    static std::atomic<uint64_t> n{1};
    return n++;
  }

  std::unique_ptr<Compiled> compile() const {
    auto c = std::make_unique<Compiled>();
    try {
      c->parser.DefineConst("pi", std::numbers::pi);
      for (const auto& [k, v] : consts_) c->parser.DefineConst(k, v);
      for (const auto& v : vars_) c->parser.DefineVar(v, &c->var);
      c->parser.SetExpr(expr_);
      c->var = 0.0;
      c->parser.Eval();  // forces parsing so unknown names are reported now
    } catch (mu::Parser::exception_type& e) {
      throw InputError(what_ + " '" + expr_ + "': " + e.GetMsg());
    }
    return c;
  }

  Compiled& local() const {
    thread_local std::unordered_map<uint64_t, std::unique_ptr<Compiled>> cache;
    auto it = cache.find(id_);
    if (it == cache.end()) it = cache.emplace(id_, compile()).first;
    return *it->second;
  }

  std::string expr_;
  std::vector<std::string> vars_;
  ExprConstants consts_;
  std::string what_;
  uint64_t id_;
};

// f and its first three derivatives by fourth-order central differences. `scale` is the parameter's natural
// length; each order uses the step that balances truncation against rounding.
void derivatives(const ExprFunction& f, double x, int order, double scale, double* out) {
  out[0] = f(x);
  out[1] = out[2] = out[3] = 0.0;
  if (order >= 1) {
    double h = 7.4e-4 * scale;  // eps^(1/5)
    out[1] = (f(x - 2 * h) - 8 * f(x - h) + 8 * f(x + h) - f(x + 2 * h)) / (12 * h);
  }
  if (order >= 2) {
    double h = 2.4e-3 * scale;  // eps^(1/6)
    out[2] = (-f(x - 2 * h) + 16 * f(x - h) - 30 * out[0] + 16 * f(x + h) - f(x + 2 * h)) / (12 * h * h);
  }
  if (order >= 3) {
    double h = 5.8e-3 * scale;  // eps^(1/7)
    out[3] = (-f(x - 3 * h) + 8 * f(x - 2 * h) - 13 * f(x - h) + 13 * f(x + h) - 8 * f(x + 2 * h) + f(x + 3 * h)) /
             (8 * h * h * h);
  }
}

void check_finite_on(const ExprFunction& f, double a, double b, const std::string& what) {
  for (int i = 0; i <= 64; ++i) {
    double x = a + (b - a) * i / 64.0;
    double v = f(x);
    if (!std::isfinite(v))
      throw InputError(what + " '" + f.text() + "' is not finite at " + std::to_string(x));
  }
}

void require_range(double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b) || !(b > a))
    throw InputError("the parameter range is empty: the end must be greater than the start");
}

class PolarExpr final : public Curve {
 public:
  PolarExpr(ExprFunction f, double t0, double t1, bool closed, double unit)
      : Curve(t0, t1, closed, "polar r=" + f.text()), f_(std::move(f)), unit_(unit), scale_((t1 - t0) / (2 * std::numbers::pi)) {}
  CurvePoint eval(double t, int order) const override {
    double r[4];
    derivatives(f_, t, order, scale_, r);
    return polar_point(t, unit_ * r[0], unit_ * r[1], unit_ * r[2], unit_ * r[3], order);
  }

 private:
  ExprFunction f_;
  double unit_, scale_;
};

class CartesianExpr final : public Curve {
 public:
  CartesianExpr(ExprFunction f, double x0, double x1, double unit)
      : Curve(x0, x1, false, "cartesian y=" + f.text()), f_(std::move(f)), unit_(unit), scale_((x1 - x0) / (2 * std::numbers::pi)) {}
  // u is x in the user's unit
  CurvePoint eval(double x, int order) const override {
    double y[4];
    derivatives(f_, x, order, scale_, y);
    CurvePoint p;
    p.p = Vec2{x, y[0]} * unit_;
    if (order >= 1) p.d1 = Vec2{1.0, y[1]} * unit_;
    if (order >= 2) p.d2 = Vec2{0.0, y[2]} * unit_;
    if (order >= 3) p.d3 = Vec2{0.0, y[3]} * unit_;
    return p;
  }

 private:
  ExprFunction f_;
  double unit_, scale_;
};

class ParametricExpr final : public Curve {
 public:
  ParametricExpr(ExprFunction fx, ExprFunction fy, double u0, double u1, bool closed, double unit)
      : Curve(u0, u1, closed, "parametric x=" + fx.text() + " y=" + fy.text()), fx_(std::move(fx)), fy_(std::move(fy)),
        unit_(unit), scale_((u1 - u0) / (2 * std::numbers::pi)) {}
  CurvePoint eval(double u, int order) const override {
    double x[4], y[4];
    derivatives(fx_, u, order, scale_, x);
    derivatives(fy_, u, order, scale_, y);
    CurvePoint p;
    p.p = Vec2{x[0], y[0]} * unit_;
    p.d1 = Vec2{x[1], y[1]} * unit_;
    p.d2 = Vec2{x[2], y[2]} * unit_;
    p.d3 = Vec2{x[3], y[3]} * unit_;
    return p;
  }

 private:
  ExprFunction fx_, fy_;
  double unit_, scale_;
};

void require_unit(double unit_m) {
  if (!(unit_m > 0.0) || !std::isfinite(unit_m)) throw InputError("the expression unit must be a positive length");
}

}  // namespace

CurvePtr make_polar_expr(const std::string& r_expr, double t_from, double t_to, bool closed, double unit_m,
                         const ExprConstants& constants) {
  require_range(t_from, t_to);
  require_unit(unit_m);
  ExprFunction f(r_expr, {"t", "theta"}, constants, "r(t)");
  check_finite_on(f, t_from, t_to, "r(t)");
  return std::make_shared<PolarExpr>(std::move(f), t_from, t_to, closed, unit_m);
}

CurvePtr make_cartesian_expr(const std::string& y_expr, double x_from_m, double x_to_m, double unit_m,
                             const ExprConstants& constants) {
  require_range(x_from_m, x_to_m);
  require_unit(unit_m);
  ExprFunction f(y_expr, {"x"}, constants, "y(x)");
  double a = x_from_m / unit_m, b = x_to_m / unit_m;
  check_finite_on(f, a, b, "y(x)");
  return std::make_shared<CartesianExpr>(std::move(f), a, b, unit_m);
}

CurvePtr make_parametric_expr(const std::string& x_expr, const std::string& y_expr, double u_from, double u_to,
                              bool closed, double unit_m, const ExprConstants& constants) {
  require_range(u_from, u_to);
  require_unit(unit_m);
  ExprFunction fx(x_expr, {"u", "t"}, constants, "x(u)");
  ExprFunction fy(y_expr, {"u", "t"}, constants, "y(u)");
  check_finite_on(fx, u_from, u_to, "x(u)");
  check_finite_on(fy, u_from, u_to, "y(u)");
  return std::make_shared<ParametricExpr>(std::move(fx), std::move(fy), u_from, u_to, closed, unit_m);
}

}  // namespace polarcam
