#include "cam/toolpath.hpp"

#include <boost/math/tools/minima.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/path.hpp"

namespace polarcam {

Vec2 Placement::pole() const { return {C * std::cos(beta), C * std::sin(beta)}; }

namespace {

std::string mm(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v * 1e3 << " mm";
  return os.str();
}

std::vector<double> sample_params(const Curve& c, int n) {
  std::vector<double> us;
  std::vector<double> cuts{c.u_begin()};
  for (double b : c.breakpoints()) cuts.push_back(b);
  cuts.push_back(c.u_end());
  int per = std::max(8, n / static_cast<int>(cuts.size() - 1));
  for (size_t k = 0; k + 1 < cuts.size(); ++k)
    for (int i = 0; i < per; ++i) us.push_back(cuts[k] + (cuts[k + 1] - cuts[k]) * i / per);
  us.push_back(c.u_end());
  return us;
}

}  // namespace

double signed_area(const Curve& c) {
  auto us = sample_params(c, 20000);
  double a = 0.0;
  Vec2 prev = c.eval(us.front(), 0).p;
  for (size_t i = 1; i < us.size(); ++i) {
    Vec2 p = c.eval(us[i], 0).p;
    a += cross(prev, p);
    prev = p;
  }
  a += cross(prev, c.eval(us.front(), 0).p);
  return 0.5 * a;
}

FoldCheck offset_speed_factor_min(const Curve& c, double d) {
  FoldCheck best{1.0, c.u_begin()};
  if (d == 0.0) return best;
  auto factor = [&](double u) { return 1.0 - d * curvature(c.eval(u, 2)); };
  auto us = sample_params(c, 4000);
  std::vector<double> f(us.size());
  for (size_t i = 0; i < us.size(); ++i) f[i] = factor(us[i]);
  for (size_t i = 0; i < us.size(); ++i) {
    if (f[i] < best.min_factor) best = {f[i], us[i]};
    // refine interior local minima by Brent's method
    if (i > 0 && i + 1 < us.size() && f[i] <= f[i - 1] && f[i] <= f[i + 1]) {
      boost::uintmax_t iters = 100;
      const auto m = boost::math::tools::brent_find_minima(factor, us[i - 1], us[i + 1],
                                                           std::numeric_limits<double>::digits / 2, iters);
      if (m.second < best.min_factor) best = {m.second, m.first};
    }
  }
  return best;
}

int tool_side_sign(const Curve& contour, const ToolSpec& tool, const TravelSpec& travel) {
  switch (tool.side) {
    case ToolSide::left: return 1;
    case ToolSide::right: return -1;
    case ToolSide::outside:
    case ToolSide::inside: break;
  }
  if (!contour.closed()) throw InputError("tool side 'outside'/'inside' needs a closed contour; use 'left' or 'right'");
  double area = signed_area(contour);
  if (travel.reverse) area = -area;
  const bool ccw = area > 0.0;  // then the left normal points inside
  return ((tool.side == ToolSide::inside) == ccw) ? 1 : -1;
}

ToolPathPtr make_tool_path(CurvePtr contour, const Placement& placement, const ToolSpec& tool,
                           const TravelSpec& travel) {
  if (!std::isfinite(placement.C) || !std::isfinite(placement.beta)) throw InputError("the placement must be finite");
  if (!(tool.radius >= 0.0) || !std::isfinite(tool.radius)) throw InputError("the tool radius must be zero or positive");
  if (travel.start_parameter && !contour->closed()) throw InputError("a start parameter applies to closed contours only");
  if (travel.start_parameter && !std::isfinite(*travel.start_parameter)) throw InputError("the start parameter must be finite");

  // signed offset relative to the direction of travel (+ left)
  const double d = tool.radius > 0.0 ? tool_side_sign(*contour, tool, travel) * tool.radius : 0.0;
  if (d == 0.0) return std::make_shared<ToolPath>(std::move(contour), placement, 0.0, travel);

  const double dc = travel.reverse ? -d : d;  // side relative to the contour's own direction
  // paths of lines and arcs are offset constructively (round convex corners)
  if (const auto* segs = path_segments(*contour)) {
    CurvePtr off = make_path(offset_path(*segs, contour->closed(), dc), contour->closed());
    TravelSpec t = travel;
    if (t.start_parameter) {
      // the offset path has its own arc-length parameter: keep the start at the same fraction of the path
      t.start_parameter = off->u_begin() + (*t.start_parameter - contour->u_begin()) /
                                               (contour->u_end() - contour->u_begin()) * (off->u_end() - off->u_begin());
    }
    return std::make_shared<ToolPath>(std::move(off), placement, 0.0, t);
  }
  // smooth curves: corners (tangent jumps at breakpoints) cannot be offset
  for (double b : contour->breakpoints()) {
    Vec2 t0 = contour->eval(std::nextafter(b, contour->u_begin()), 1).d1, t1 = contour->eval(b, 1).d1;
    double turn = std::atan2(cross(t0, t1), dot(t0, t1));
    if (std::abs(turn) > 1e-7)
      throw InputError("the contour has a corner at parameter " + std::to_string(b) + " that a tool of radius " +
                       mm(tool.radius) + " cannot follow");
  }
  FoldCheck fc = offset_speed_factor_min(*contour, dc);
  if (!(fc.min_factor > 1e-9)) {
    CurvePoint cp = contour->eval(fc.u, 2);
    double rho = 1.0 / std::abs(curvature(cp));
    throw InputError("the tool radius " + mm(tool.radius) + " is larger than the concave radius of curvature " +
                     mm(rho) + " of the contour at parameter " + significant(fc.u, 9) + " (point " + mm(cp.p.x) +
                     ", " + mm(cp.p.y) + "): the offset path would cusp or fold");
  }
  return std::make_shared<ToolPath>(std::move(contour), placement, d, travel);
}

ToolPath::ToolPath(CurvePtr contour, const Placement& placement, double offset, const TravelSpec& travel)
    : Curve(contour->u_begin(), contour->u_end(), contour->closed(), contour->name()),
      contour_(std::move(contour)), placement_(placement), pole_(placement.pole()), d_(offset),
      reverse_(travel.reverse) {
  const double u0 = contour_->u_begin(), u1 = contour_->u_end(), L = u1 - u0;
  if (travel.start_parameter) {
    shift_ = std::fmod(*travel.start_parameter - u0, L);
    if (shift_ < 0) shift_ += L;
  }
  // breakpoints in tool-path parameter: invert contour_parameter()
  auto to_tp = [&](double b) {
    double w;
    if (!contour_->closed()) {
      w = reverse_ ? u1 - b : b - u0;
    } else {
      w = reverse_ ? std::fmod(shift_ - (b - u0) + 2 * L, L) : std::fmod(b - u0 - shift_ + 2 * L, L);
    }
    return u0 + w;
  };
  for (double b : contour_->breakpoints()) breaks_.push_back(to_tp(b));
  if (shift_ > 0.0) breaks_.push_back(to_tp(u0));  // the seam
  std::sort(breaks_.begin(), breaks_.end());
  breaks_.erase(std::remove_if(breaks_.begin(), breaks_.end(),
                               [&](double b) { return !(b > u0 + 1e-12 * L && b < u1 - 1e-12 * L); }),
                breaks_.end());
  breaks_.erase(std::unique(breaks_.begin(), breaks_.end()), breaks_.end());
}

double ToolPath::contour_parameter(double u) const {
  const double u0 = u_begin(), u1 = u_end(), L = u1 - u0;
  double w = u - u0;  // distance along travel, in parameter units
  if (!reverse_ && shift_ == 0.0) return u;
  if (!closed()) return u1 - w;
  double v = reverse_ ? shift_ - w : shift_ + w;
  if (v < 0) v += L;
  if (v >= L) v -= L;
  return u0 + v;
}

CurvePoint ToolPath::eval(double u, int order) const {
  const int base_order = d_ != 0.0 ? std::min(order + 1, 3) : order;
  CurvePoint c = contour_->eval(contour_parameter(u), base_order);
  if (reverse_) {
    c.d1 = -c.d1;
    c.d3 = -c.d3;
  }
  CurvePoint q;
  if (d_ == 0.0) {
    q = c;
  } else {
    double v = norm(c.d1);
    Vec2 T = c.d1 / v;
    double k = cross(c.d1, c.d2) / (v * v * v);
    double f = 1.0 - d_ * k;
    if (!(f > 0.0))
      throw InputError("the tool-radius offset folds at contour parameter " + std::to_string(contour_parameter(u)) +
                       " (radius of curvature " + mm(1.0 / std::abs(k)) + ")");
    q.p = c.p + perp(T) * d_;
    if (order >= 1) q.d1 = c.d1 * f;
    if (order >= 2) {
      double kp = curvature_derivative(c);
      q.d2 = c.d2 * f - c.d1 * (d_ * kp);
    }
  }
  q.p = q.p - pole_;
  return q;
}

}  // namespace polarcam
