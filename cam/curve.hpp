#pragma once
// A contour: a plane curve P(u) in the contour's own frame (origin = contour pole O1, metres), over a parameter
// interval [u_begin, u_end]. Curves are immutable after construction and safe to evaluate from several threads.
#include <memory>
#include <string>
#include <vector>

#include "cam/vec2.hpp"

namespace polarcam {

// Position and parameter derivatives at one parameter value; derivatives above the requested order are zero.
struct CurvePoint {
  Vec2 p, d1, d2, d3;
};

class Curve {
 public:
  virtual ~Curve() = default;

  double u_begin() const { return u0_; }
  double u_end() const { return u1_; }
  bool closed() const { return closed_; }
  // Short description for reports and tape provenance, e.g. "limacon a=0.0508 m b=0.0762 m".
  const std::string& name() const { return name_; }

  // Position and derivatives up to `order` (0..3) with respect to u.
  virtual CurvePoint eval(double u, int order) const = 0;

  // Interior parameter values where the curve is less smooth than analytic (spline knots, joints of lines and
  // arcs, seams). Approximation and root finding never straddle them. Sorted, strictly inside (u_begin, u_end).
  virtual std::vector<double> breakpoints() const { return {}; }

  // Size of the numbers a position is computed from, beyond the position itself (metres): a point of a placed
  // tool path is P + d N - O, so it carries rounding errors of about eps (|P| + |d| + |O|) even where it is
  // close to the origin. Approximation tolerances use it; 0 for a curve evaluated directly.
  virtual double rounding_scale() const { return 0.0; }

 protected:
  Curve(double u0, double u1, bool closed, std::string name)
      : u0_(u0), u1_(u1), closed_(closed), name_(std::move(name)) {}

 private:
  double u0_, u1_;
  bool closed_;
  std::string name_;
};

using CurvePtr = std::shared_ptr<const Curve>;

// Signed curvature (Eq. 3.4 in parametric form): kappa = cross(P', P'') / |P'|^3, positive when the curve turns left.
double curvature(const CurvePoint& c);
// d kappa / du, from P', P'', P'''.
double curvature_derivative(const CurvePoint& c);

// Arc length between two parameter values (adaptive Gauss-Legendre on |P'|, relative accuracy ~1e-13),
// splitting at breakpoints.
double arc_length(const Curve& c, double ua, double ub);

}  // namespace polarcam
