#include "cam/theta_rho_path.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cam/error.hpp"

namespace polarcam {
namespace {

bool same_place(const ThetaRho& a, const ThetaRho& b) {
  if (std::abs(a.rho - b.rho) > 1e-12) return false;
  if (a.rho <= 1e-12 && b.rho <= 1e-12) return true;
  const double turns = (b.theta - a.theta) / (2.0 * std::numbers::pi);
  return std::abs(turns - std::round(turns)) * (2.0 * std::numbers::pi) <= 1e-9;
}

}  // namespace

ThetaRhoPath::ThetaRhoPath(std::vector<ThetaRho> v, bool closed, std::string name)
    : Curve(0.0, static_cast<double>(v.size() - 1), closed, std::move(name)), v_(std::move(v)) {}

void ThetaRhoPath::locate(double u, size_t& k, double& f) const {
  const size_t last = v_.size() - 2;
  double fl = std::floor(u);
  if (!(fl >= 0.0)) fl = 0.0;
  k = std::min(static_cast<size_t>(fl), last);
  f = u - static_cast<double>(k);
}

CurvePoint ThetaRhoPath::eval(double u, int order) const {
  size_t k;
  double f;
  locate(u, k, f);
  const ThetaRho& a = v_[k];
  const ThetaRho& b = v_[k + 1];
  const double dth = b.theta - a.theta, drho = b.rho - a.rho;
  const double th = a.theta + dth * f, rho = a.rho + drho * f;
  const double c = std::cos(th), s = std::sin(th);
  CurvePoint p;
  p.p = {rho * c, rho * s};
  if (order >= 1) p.d1 = Vec2{drho * c, drho * s} + rho * dth * Vec2{-s, c};
  if (order >= 2) p.d2 = 2.0 * drho * dth * Vec2{-s, c} + rho * dth * dth * Vec2{-c, -s};
  if (order >= 3) p.d3 = 3.0 * drho * dth * dth * Vec2{-c, -s} + rho * dth * dth * dth * Vec2{s, -c};
  return p;
}

std::vector<double> ThetaRhoPath::breakpoints() const {
  std::vector<double> b;
  b.reserve(v_.size() > 2 ? v_.size() - 2 : 0);
  for (size_t k = 1; k + 1 < v_.size(); ++k) b.push_back(static_cast<double>(k));
  return b;
}

CurvePtr make_theta_rho_path(std::vector<ThetaRho> v, std::string name) {
  if (v.size() < 2) throw InputError("a theta-rho path needs at least two distinct points");
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string where = "point " + std::to_string(i + 1);
    if (!std::isfinite(v[i].theta) || !std::isfinite(v[i].rho)) throw InputError("not a finite number", where);
    if (v[i].rho < 0.0) throw InputError("rho is negative", where);
    if (i > 0 && v[i].theta == v[i - 1].theta && v[i].rho == v[i - 1].rho)
      throw InputError("repeats the point before it", where);
  }
  const bool closed = v.size() > 2 && same_place(v.front(), v.back());
  return std::make_shared<ThetaRhoPath>(std::move(v), closed, std::move(name));
}

const ThetaRhoPath* as_theta_rho_path(const Curve& c) { return dynamic_cast<const ThetaRhoPath*>(&c); }

double theta_rho_segment_length(const ThetaRho& a, const ThetaRho& b) {
  const double A = std::abs(b.theta - a.theta), drho = b.rho - a.rho;
  if (drho == 0.0) return a.rho * A;
  if (A == 0.0) return std::abs(drho);
  // ds/df = sqrt(drho^2 + (rho A)^2); with w = rho A and c = |drho| the integral is
  // (G(wb) - G(wa)) / (drho A), G(w) = (w S + c^2 asinh(w / c)) / 2, S = sqrt(w^2 + c^2); both differences are
  // rationalised so that nothing cancels when drho is small.
  const double c = std::abs(drho), wa = a.rho * A, wb = b.rho * A;
  const double Sa = std::hypot(wa, c), Sb = std::hypot(wb, c);
  const double first = (wb + wa) * (wb * wb + wa * wa + c * c) / (wb * Sb + wa * Sa);
  const double x = drho * A * (wb + wa) / (wb * Sa + wa * Sb);
  const double second = c * c * std::asinh(x) / (drho * A);
  return 0.5 * (first + second);
}

}  // namespace polarcam
