#include "cam/path.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "cam/error.hpp"
#include "cam/format.hpp"

namespace polarcam {
namespace {

double seg_length(const PathSegment& s) {
  if (s.kind == PathSegment::Kind::line) return norm(s.to - s.from);
  return norm(s.from - s.center) * std::abs(s.sweep);
}

Vec2 tangent_at_start(const PathSegment& s) {
  if (s.kind == PathSegment::Kind::line) return (s.to - s.from) / norm(s.to - s.from);
  Vec2 r = (s.from - s.center) / norm(s.from - s.center);
  return s.sweep > 0 ? perp(r) : -perp(r);
}

Vec2 tangent_at_end(const PathSegment& s) {
  if (s.kind == PathSegment::Kind::line) return (s.to - s.from) / norm(s.to - s.from);
  Vec2 r = (s.to - s.center) / norm(s.to - s.center);
  return s.sweep > 0 ? perp(r) : -perp(r);
}

class Path final : public Curve {
 public:
  Path(std::vector<PathSegment> segs, std::vector<double> starts, bool closed)
      : Curve(0.0, starts.back(), closed, describe(segs, closed)), segs_(std::move(segs)), starts_(std::move(starts)) {}

  CurvePoint eval(double u, int order) const override {
    auto it = std::upper_bound(starts_.begin(), starts_.end() - 1, u);
    size_t i = (it == starts_.begin()) ? 0 : static_cast<size_t>(it - starts_.begin()) - 1;
    i = std::min(i, segs_.size() - 1);
    const PathSegment& s = segs_[i];
    double t = u - starts_[i];
    CurvePoint p;
    if (s.kind == PathSegment::Kind::line) {
      Vec2 dir = (s.to - s.from) / norm(s.to - s.from);
      p.p = s.from + dir * t;
      if (order >= 1) p.d1 = dir;
      return p;
    }
    Vec2 r0 = s.from - s.center;
    double R = norm(r0), a0 = std::atan2(r0.y, r0.x), sg = s.sweep > 0 ? 1.0 : -1.0;
    double a = a0 + sg * t / R, c = std::cos(a), sn = std::sin(a);
    p.p = s.center + Vec2{R * c, R * sn};
    if (order >= 1) p.d1 = Vec2{-sn, c} * sg;
    if (order >= 2) p.d2 = Vec2{-c, -sn} / R;
    if (order >= 3) p.d3 = Vec2{sn, -c} * (sg / (R * R));
    return p;
  }

  std::vector<double> breakpoints() const override {
    return std::vector<double>(starts_.begin() + 1, starts_.end() - 1);
  }

  const std::vector<PathSegment>& segments() const { return segs_; }

 private:
  static std::string describe(const std::vector<PathSegment>& segs, bool closed) {
    size_t lines = 0;
    for (const auto& s : segs) lines += s.kind == PathSegment::Kind::line;
    std::ostringstream os;
    os << (closed ? "closed" : "open") << " path of " << lines << " lines and " << segs.size() - lines << " arcs";
    return os.str();
  }

  std::vector<PathSegment> segs_;
  std::vector<double> starts_;
};

std::string corner_name(size_t i) { return "the corner after segment " + std::to_string(i + 1); }

}  // namespace

PathSegment make_arc_segment(Vec2 from, Vec2 center, double sweep) {
  PathSegment s;
  s.kind = PathSegment::Kind::arc;
  s.from = from;
  s.center = center;
  s.sweep = sweep;
  Vec2 r = from - center;
  double c = std::cos(sweep), sn = std::sin(sweep);
  s.to = center + Vec2{r.x * c - r.y * sn, r.x * sn + r.y * c};
  return s;
}

PathSegment make_arc_segment_to(Vec2 from, Vec2 to, Vec2 center, bool ccw) {
  double r0 = norm(from - center), r1 = norm(to - center);
  if (!(r0 > 0.0)) throw InputError("an arc's centre coincides with its start");
  if (std::abs(r0 - r1) > 1e-6 * r0)
    throw InputError("an arc's end is not on its circle (radius " + std::to_string(r0) + " m at the start, " +
                     std::to_string(r1) + " m at the end)");
  double a0 = std::atan2(from.y - center.y, from.x - center.x), a1 = std::atan2(to.y - center.y, to.x - center.x);
  double sweep = a1 - a0;
  constexpr double two_pi = 2.0 * std::numbers::pi;
  if (ccw) {
    while (sweep <= 0.0) sweep += two_pi;
  } else {
    while (sweep >= 0.0) sweep -= two_pi;
  }
  PathSegment s;
  s.kind = PathSegment::Kind::arc;
  s.from = from;
  s.to = to;
  s.center = center;
  s.sweep = sweep;
  return s;
}

CurvePtr make_path(std::vector<PathSegment> segs, bool closed) {
  if (segs.empty()) throw InputError("a path needs at least one segment");
  std::vector<double> starts{0.0};
  for (size_t i = 0; i < segs.size(); ++i) {
    double L = seg_length(segs[i]);
    if (!(L > 0.0) || !std::isfinite(L)) throw InputError("segment " + std::to_string(i + 1) + " of the path has no length");
    if (i > 0 && norm(segs[i].from - segs[i - 1].to) > 1e-9 * std::max(1.0, norm(segs[i].from)))
      throw InputError("segment " + std::to_string(i + 1) + " does not start where segment " + std::to_string(i) + " ends");
    starts.push_back(starts.back() + L);
  }
  if (closed && norm(segs.back().to - segs.front().from) > 1e-9 * std::max(1.0, norm(segs.front().from)))
    throw InputError("the path is declared closed but its last segment does not end at its start");
  return std::make_shared<Path>(std::move(segs), std::move(starts), closed);
}

std::vector<PathSegment> offset_path(const std::vector<PathSegment>& segs, bool closed, double d) {
  if (d == 0.0) return segs;
  std::vector<PathSegment> off;
  off.reserve(2 * segs.size());
  auto shifted = [&](size_t i) {
    const PathSegment& s = segs[i];
    PathSegment o = s;
    if (s.kind == PathSegment::Kind::line) {
      Vec2 n = perp((s.to - s.from) / norm(s.to - s.from)) * d;
      o.from = s.from + n;
      o.to = s.to + n;
    } else {
      double R = norm(s.from - s.center);
      double Rn = s.sweep > 0 ? R - d : R + d;  // the left normal of a counter-clockwise arc points to its centre
      if (!(Rn > 0.0))
        throw InputError("the tool radius folds the offset of arc segment " + std::to_string(i + 1) + " (arc radius " +
                         significant(R * 1e3, 6) + " mm on the tool's side)");
      o.from = s.center + (s.from - s.center) * (Rn / R);
      o.to = s.center + (s.to - s.center) * (Rn / R);
    }
    return o;
  };
  const size_t n = segs.size();
  for (size_t i = 0; i < n; ++i) {
    off.push_back(shifted(i));
    bool has_next = closed || i + 1 < n;
    if (!has_next) break;
    const PathSegment& a = segs[i];
    const PathSegment& b = segs[(i + 1) % n];
    Vec2 tin = tangent_at_end(a), tout = tangent_at_start(b);
    double turn = std::atan2(cross(tin, tout), dot(tin, tout));
    if (std::abs(turn) < 1e-9) continue;
    if (turn * d > 0.0)
      throw InputError("the tool cannot follow " + corner_name(i) +
                       ": it is a sharp concave corner on the tool's side (radius of curvature 0)");
    Vec2 corner = a.to;
    off.push_back(make_arc_segment(corner + perp(tin) * d, corner, turn));
  }
  // The pieces join by construction; snap tiny rounding gaps so make_path accepts them.
  for (size_t i = 1; i < off.size(); ++i) off[i].from = off[i - 1].to;
  if (closed) off.front().from = off.back().to;
  return off;
}

const std::vector<PathSegment>* path_segments(const Curve& c) {
  auto* p = dynamic_cast<const Path*>(&c);
  return p ? &p->segments() : nullptr;
}

}  // namespace polarcam
