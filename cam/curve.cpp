#include "cam/curve.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "cam/error.hpp"

namespace polarcam {

double curvature(const CurvePoint& c) {
  double v = norm(c.d1);
  return cross(c.d1, c.d2) / (v * v * v);
}

double curvature_derivative(const CurvePoint& c) {
  double v2 = dot(c.d1, c.d1), v = std::sqrt(v2);
  return cross(c.d1, c.d3) / (v2 * v) - 3.0 * cross(c.d1, c.d2) * dot(c.d1, c.d2) / (v2 * v2 * v);
}

namespace {

// 10-point Gauss-Legendre nodes and weights on [-1, 1].
constexpr std::array<double, 5> kGLx{0.1488743389816312, 0.4333953941292472, 0.6794095682990244,
                                     0.8650633666889845, 0.9739065285171717};
constexpr std::array<double, 5> kGLw{0.2955242247147529, 0.2692667193099963, 0.2190863625159820,
                                     0.1494513491505806, 0.0666713443086881};

double gl10(const Curve& c, double a, double b) {
  double h = 0.5 * (b - a), m = 0.5 * (a + b), s = 0.0;
  for (size_t i = 0; i < kGLx.size(); ++i)
    s += kGLw[i] * (norm(c.eval(m - h * kGLx[i], 1).d1) + norm(c.eval(m + h * kGLx[i], 1).d1));
  return s * h;
}

// At most this many halvings over a whole length, and a few more for each piece between breakpoints: some 20 million
// evaluations of the curve, a few seconds. A smooth path of thousands of turns takes far fewer; beyond it the path
// oscillates faster than any machine could follow, and its length (which the depth limit alone would reach only
// after 2^40 halvings, a run without end) is refused.
constexpr long kMaxHalvings = 1L << 20;

double adaptive(const Curve& c, double a, double b, double whole, int depth, long& budget) {
  if (--budget < 0)
    throw InputError("the path has too much detail to measure its length (more than " + std::to_string(kMaxHalvings) +
                     " pieces): it oscillates faster than a machine can follow; check the contour's definition");
  double m = 0.5 * (a + b);
  double l = gl10(c, a, m), r = gl10(c, m, b);
  if (depth >= 40 || std::abs(l + r - whole) <= 1e-14 * std::max(std::abs(whole), 1e-300)) return l + r;
  return adaptive(c, a, m, l, depth + 1, budget) + adaptive(c, m, b, r, depth + 1, budget);
}

}  // namespace

double arc_length(const Curve& c, double ua, double ub) {
  if (ub < ua) return -arc_length(c, ub, ua);
  std::vector<double> cuts{ua};
  for (double k : c.breakpoints())
    if (k > ua && k < ub) cuts.push_back(k);
  cuts.push_back(ub);
  double total = 0.0;
  long budget = kMaxHalvings + 64 * static_cast<long>(cuts.size());  // a few for each smooth piece besides
  for (size_t i = 0; i + 1 < cuts.size(); ++i)
    if (cuts[i + 1] > cuts[i]) total += adaptive(c, cuts[i], cuts[i + 1], gl10(c, cuts[i], cuts[i + 1]), 0, budget);
  return total;
}

}  // namespace polarcam
