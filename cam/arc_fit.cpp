#include "cam/arc_fit.hpp"

#include <boost/math/tools/minima.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "cam/error.hpp"

namespace polarcam {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kSamples = 32;   // deviation samples per candidate (then refined at the worst one)
constexpr int kMaxDepth = 50;  // halvings of one span

std::string where(const Curve& c, double u) {
  Vec2 p = c.eval(u, 0).p;
  std::ostringstream os;
  os.precision(6);
  os << "parameter " << u << " (x = " << p.x * 1e3 << " mm, y = " << p.y * 1e3 << " mm)";
  return os.str();
}

// Largest distance from the curve over (ua, ub) to `seg`: samples, then Brent's method around the worst sample.
double deviation(const Curve& c, double ua, double ub, const PathSegment& seg) {
  auto d = [&](double u) { return distance_to_segment(seg, c.eval(u, 0).p); };
  const double h = (ub - ua) / kSamples;
  double best = 0.0;
  int bi = 0;
  for (int i = 1; i < kSamples; ++i) {
    double v = d(ua + h * i);
    if (!std::isfinite(v)) return v;
    if (v > best) {
      best = v;
      bi = i;
    }
  }
  if (bi == 0) return best;
  boost::uintmax_t iters = 60;
  const auto m = boost::math::tools::brent_find_minima([&](double u) { return -d(u); }, ua + h * (bi - 1),
                                                       ua + h * (bi + 1), std::numeric_limits<double>::digits / 2, iters);
  return std::max(best, -m.second);
}

// The arc from a through m to b, or false when the three points are (numerically) collinear.
bool arc_through(Vec2 a, Vec2 m, Vec2 b, PathSegment& s) {
  const Vec2 u = m - a, v = b - a;
  const double D = 2.0 * cross(u, v);
  const double uu = dot(u, u), vv = dot(v, v);
  if (!(std::abs(D) > 1e-12 * (uu + vv)) || !(vv > 0.0)) return false;
  const Vec2 c = a + Vec2{(v.y * uu - u.y * vv) / D, (u.x * vv - v.x * uu) / D};
  const Vec2 ra = a - c, rb = b - c;
  double sweep = std::atan2(cross(ra, rb), dot(ra, rb));  // (-pi, pi]
  if (D > 0 && sweep <= 0) sweep += kTwoPi;               // counter-clockwise a -> m -> b
  if (D < 0 && sweep >= 0) sweep -= kTwoPi;
  s.kind = PathSegment::Kind::arc;
  s.from = a;
  s.to = b;
  s.center = c;
  s.sweep = sweep;
  return std::isfinite(c.x) && std::isfinite(c.y);
}

}  // namespace

double segment_length(const PathSegment& s) {
  if (s.kind == PathSegment::Kind::line) return norm(s.to - s.from);
  return norm(s.from - s.center) * std::abs(s.sweep);
}

double distance_to_segment(const PathSegment& s, Vec2 p) {
  if (s.kind == PathSegment::Kind::line) {
    const Vec2 d = s.to - s.from;
    const double L2 = dot(d, d);
    if (!(L2 > 0.0)) return norm(p - s.from);
    const double t = std::clamp(dot(p - s.from, d) / L2, 0.0, 1.0);
    return norm(p - (s.from + d * t));
  }
  const Vec2 a0 = s.from - s.center, v = p - s.center;
  const double R = norm(a0), r = norm(v);
  double phi = std::atan2(cross(a0, v), dot(a0, v));  // angle from the start, (-pi, pi]
  if (s.sweep < 0) phi = -phi;
  if (phi < 0) phi += kTwoPi;
  if (phi <= std::abs(s.sweep)) return std::abs(r - R);
  return std::min(norm(p - s.from), norm(p - s.to));
}

ArcFit fit_lines_and_arcs(const Curve& c, const ArcFitOptions& opt) {
  if (!(opt.tolerance > 0.0) || !std::isfinite(opt.tolerance)) throw InputError("the chord tolerance must be a positive length");
  ArcFit fit;
  std::vector<double> cuts{c.u_begin()};
  for (double b : c.breakpoints()) cuts.push_back(b);
  cuts.push_back(c.u_end());
  const Vec2 first = c.eval(c.u_begin(), 0).p;

  struct Span {
    double ua, ub;
    Vec2 pa, pb;
    int depth;
  };
  std::vector<Span> stack;
  for (size_t k = cuts.size() - 1; k-- > 0;) {
    Vec2 pb = (k + 2 == cuts.size() && c.closed()) ? first : c.eval(cuts[k + 1], 0).p;
    stack.push_back({cuts[k], cuts[k + 1], c.eval(cuts[k], 0).p, pb, 0});
  }
  while (!stack.empty()) {
    Span sp = stack.back();
    stack.pop_back();
    if (!std::isfinite(sp.pa.x) || !std::isfinite(sp.pa.y) || !std::isfinite(sp.pb.x) || !std::isfinite(sp.pb.y))
      throw InputError("the path is not finite near " + where(c, sp.ua));
    const double um = 0.5 * (sp.ua + sp.ub);
    const Vec2 pm = c.eval(um, 0).p;
    PathSegment line;
    line.from = sp.pa;
    line.to = sp.pb;
    double dev = deviation(c, sp.ua, sp.ub, line);
    bool ok = dev <= opt.tolerance && norm(sp.pb - sp.pa) > 0.0;
    PathSegment seg = line;
    if (!ok) {
      PathSegment arc;
      if (arc_through(sp.pa, pm, sp.pb, arc) && std::abs(arc.sweep) <= opt.max_sweep * (1.0 + 1e-9)) {
        double da = deviation(c, sp.ua, sp.ub, arc);
        if (da <= opt.tolerance) {
          ok = true;
          seg = arc;
          dev = da;
        }
      }
    }
    if (ok) {
      fit.segments.push_back(seg);
      fit.max_deviation = std::max(fit.max_deviation, dev);
      (seg.kind == PathSegment::Kind::line ? fit.lines : fit.arcs) += 1;
      if (fit.segments.size() > opt.max_segments)
        throw InputError("approximating the path within the chord tolerance takes more than " +
                         std::to_string(opt.max_segments) + " lines and arcs: raise the tolerance");
      continue;
    }
    if (sp.depth >= kMaxDepth || !(um > sp.ua && um < sp.ub))
      throw InputError("cannot approximate the path by lines and arcs within the chord tolerance near " + where(c, um));
    stack.push_back({um, sp.ub, pm, sp.pb, sp.depth + 1});
    stack.push_back({sp.ua, um, sp.pa, pm, sp.depth + 1});
  }
  return fit;
}

}  // namespace polarcam
