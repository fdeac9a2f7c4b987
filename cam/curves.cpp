#include "cam/curves.hpp"

#include <cmath>
#include <numbers>
#include <numeric>
#include <sstream>

#include "cam/error.hpp"

namespace polarcam {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::string fmt_m(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v << " m";
  return os.str();
}

void require_positive(double v, const char* what) {
  if (!(v > 0.0) || !std::isfinite(v)) throw InputError(std::string(what) + " must be positive");
}

void require_range(double from, double to, const char* what) {
  if (!std::isfinite(from) || !std::isfinite(to) || !(to > from))
    throw InputError(std::string("the ") + what + " range is empty: the end must be greater than the start");
}

class Circle final : public Curve {
 public:
  Circle(Vec2 c, double r) : Curve(0.0, kTwoPi, true, "circle radius=" + fmt_m(r)), c_(c), r_(r) {}
  CurvePoint eval(double u, int order) const override {
    double s = std::sin(u), co = std::cos(u);
    CurvePoint p;
    p.p = c_ + Vec2{r_ * co, r_ * s};
    if (order >= 1) p.d1 = {-r_ * s, r_ * co};
    if (order >= 2) p.d2 = {-r_ * co, -r_ * s};
    if (order >= 3) p.d3 = {r_ * s, -r_ * co};
    return p;
  }

 private:
  Vec2 c_;
  double r_;
};

class Line final : public Curve {
 public:
  Line(Vec2 a, Vec2 b) : Curve(0.0, norm(b - a), false, "line length=" + fmt_m(norm(b - a))), a_(a) {
    dir_ = (b - a) / norm(b - a);
  }
  CurvePoint eval(double u, int order) const override {
    CurvePoint p;
    p.p = a_ + dir_ * u;
    if (order >= 1) p.d1 = dir_;
    return p;
  }

 private:
  Vec2 a_, dir_;
};

// y = f(x) graph curve with analytic derivatives provided by F(x) -> {y, y', y'', y'''}.
template <class F>
class Graph final : public Curve {
 public:
  Graph(double x0, double x1, std::string name, F f) : Curve(x0, x1, false, std::move(name)), f_(f) {}
  CurvePoint eval(double x, int order) const override {
    double y[4];
    f_(x, y);
    CurvePoint p;
    p.p = {x, y[0]};
    if (order >= 1) p.d1 = {1.0, y[1]};
    if (order >= 2) p.d2 = {0.0, y[2]};
    if (order >= 3) p.d3 = {0.0, y[3]};
    return p;
  }

 private:
  F f_;
};

template <class F>
class PolarAnalytic final : public Curve {
 public:
  PolarAnalytic(double t0, double t1, bool closed, std::string name, F f)
      : Curve(t0, t1, closed, std::move(name)), f_(f) {}
  CurvePoint eval(double t, int order) const override {
    double r[4];
    f_(t, r);
    return polar_point(t, r[0], r[1], r[2], r[3], order);
  }

 private:
  F f_;
};

}  // namespace

CurvePoint polar_point(double t, double rho, double rho1, double rho2, double rho3, int order) {
  double s = std::sin(t), c = std::cos(t);
  Vec2 e{c, s}, ep{-s, c};
  CurvePoint p;
  p.p = e * rho;
  if (order >= 1) p.d1 = e * rho1 + ep * rho;
  if (order >= 2) p.d2 = e * (rho2 - rho) + ep * (2.0 * rho1);
  if (order >= 3) p.d3 = e * (rho3 - 3.0 * rho1) + ep * (3.0 * rho2 - rho);
  return p;
}

CurvePtr make_circle(Vec2 center, double radius) {
  require_positive(radius, "the circle's radius");
  return std::make_shared<Circle>(center, radius);
}

CurvePtr make_line(Vec2 a, Vec2 b) {
  if (!(norm(b - a) > 0.0)) throw InputError("the line's start and end are the same point");
  return std::make_shared<Line>(a, b);
}

CurvePtr make_witch(double a, double x_from, double x_to) {
  require_positive(a, "the witch's a");
  require_range(x_from, x_to, "x");
  auto f = [a](double x, double* y) {
    double a2 = a * a, a3 = a2 * a, x2 = x * x, d = x2 + 4.0 * a2, d2 = d * d;
    y[0] = 8.0 * a3 / d;
    y[1] = -16.0 * a3 * x / d2;
    y[2] = 16.0 * a3 * (3.0 * x2 - 4.0 * a2) / (d2 * d);
    y[3] = 192.0 * a3 * x * (4.0 * a2 - x2) / (d2 * d2);
  };
  return std::make_shared<Graph<decltype(f)>>(x_from, x_to, "witch a=" + fmt_m(a), f);
}

CurvePtr make_serpentine(double a, double b, double x_from, double x_to) {
  require_positive(a, "the serpentine's a");
  if (!std::isfinite(b) || b == 0.0) throw InputError("the serpentine's b must be non-zero");
  require_range(x_from, x_to, "x");
  auto f = [a, b](double x, double* y) {
    double a2 = a * a, x2 = x * x, d = a2 + x2, d2 = d * d, ab = a * b;
    y[0] = ab * x / d;
    y[1] = ab * (a2 - x2) / d2;
    y[2] = 2.0 * ab * x * (x2 - 3.0 * a2) / (d2 * d);
    y[3] = -6.0 * ab * (x2 * x2 - 6.0 * a2 * x2 + a2 * a2) / (d2 * d2);
  };
  return std::make_shared<Graph<decltype(f)>>(x_from, x_to, "serpentine a=" + fmt_m(a) + " b=" + fmt_m(b), f);
}

CurvePtr make_limacon(double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b) || (a == 0.0 && b == 0.0))
    throw InputError("the limacon's a and b must be finite and not both zero");
  auto f = [a, b](double t, double* r) {
    double c = std::cos(t), s = std::sin(t);
    r[0] = b + a * c;
    r[1] = -a * s;
    r[2] = -a * c;
    r[3] = a * s;
  };
  return std::make_shared<PolarAnalytic<decltype(f)>>(0.0, kTwoPi, true, "limacon a=" + fmt_m(a) + " b=" + fmt_m(b), f);
}

CurvePtr make_spiral(double a, double b, double t_from, double t_to) {
  if (!std::isfinite(a) || !std::isfinite(b) || b == 0.0) throw InputError("the spiral's b (growth per radian) must be non-zero");
  require_range(t_from, t_to, "theta");
  auto f = [a, b](double t, double* r) {
    r[0] = a + b * t;
    r[1] = b;
    r[2] = 0.0;
    r[3] = 0.0;
  };
  return std::make_shared<PolarAnalytic<decltype(f)>>(t_from, t_to, false, "spiral a=" + fmt_m(a) + " b=" + fmt_m(b) + "/rad", f);
}

CurvePtr make_rose(double a, int p, int q) {
  require_positive(a, "the rose's a");
  if (p <= 0 || q <= 0) throw InputError("the rose's k = p/q must be positive");
  int g = std::gcd(p, q);
  p /= g;
  q /= g;
  double k = static_cast<double>(p) / q;
  double period = ((p * q) % 2 == 1) ? std::numbers::pi * q : kTwoPi * q;
  auto f = [a, k](double t, double* r) {
    double c = std::cos(k * t), s = std::sin(k * t);
    r[0] = a * c;
    r[1] = -a * k * s;
    r[2] = -a * k * k * c;
    r[3] = a * k * k * k * s;
  };
  return std::make_shared<PolarAnalytic<decltype(f)>>(0.0, period, true,
                                                      "rose a=" + fmt_m(a) + " k=" + std::to_string(p) + "/" + std::to_string(q), f);
}

}  // namespace polarcam
