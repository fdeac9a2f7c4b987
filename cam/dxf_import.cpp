#include "cam/dxf_import.hpp"

#include <dxflib/dl_creationadapter.h>
#include <dxflib/dl_dxf.h>

#include <cmath>
#include <fstream>
#include <map>
#include <numbers>

#include "cam/error.hpp"

namespace polarcam {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

class Collector final : public DL_CreationAdapter {
 public:
  explicit Collector(const DxfOptions& o) : o_(o) {}

  std::vector<PathSegment> segs;
  std::map<std::string, int> refused;  // entity kind -> count
  std::string error;

  void addLine(const DL_LineData& d) override {
    if (!take()) return;
    PathSegment s;
    s.from = pt(d.x1, d.y1);
    s.to = pt(d.x2, d.y2);
    if (norm(s.to - s.from) > 0) segs.push_back(s);
  }
  void addArc(const DL_ArcData& d) override {
    if (!take()) return;
    double a1 = d.angle1 * kDeg, a2 = d.angle2 * kDeg, sweep = a2 - a1;
    while (sweep <= 0) sweep += 2 * std::numbers::pi;  // DXF arcs run counter-clockwise from angle1 to angle2
    arc(d.cx, d.cy, d.radius, a1, sweep);
  }
  void addCircle(const DL_CircleData& d) override {
    if (!take()) return;
    arc(d.cx, d.cy, d.radius, 0.0, 2 * std::numbers::pi);
  }
  void addPolyline(const DL_PolylineData& d) override {
    flush_polyline();
    in_poly_ = take();
    poly_closed_ = d.flags & 1;
    verts_.clear();
  }
  void addVertex(const DL_VertexData& d) override {
    if (in_poly_) verts_.push_back(d);
  }
  void endEntity() override { flush_polyline(); }
  void endSection() override { flush_polyline(); }

  void addSpline(const DL_SplineData&) override { refuse("SPLINE"); }
  void addEllipse(const DL_EllipseData&) override { refuse("ELLIPSE"); }
  void addPoint(const DL_PointData&) override {}
  void addXLine(const DL_XLineData&) override { refuse("XLINE"); }
  void addRay(const DL_RayData&) override { refuse("RAY"); }

  void flush_polyline() {
    if (!in_poly_) return;
    in_poly_ = false;
    const size_t n = verts_.size();
    for (size_t i = 0; i + 1 < n + (poly_closed_ ? 1 : 0); ++i) {
      const DL_VertexData& a = verts_[i];
      const DL_VertexData& b = verts_[(i + 1) % n];
      Vec2 p = pt(a.x, a.y), q = pt(b.x, b.y);
      if (norm(q - p) == 0) continue;
      double bulge = mirrored() ? -a.bulge : a.bulge;
      if (std::abs(bulge) < 1e-12) {
        PathSegment s;
        s.from = p;
        s.to = q;
        segs.push_back(s);
      } else {
        // bulge = tan(included angle / 4), positive counter-clockwise; the centre sits on the chord's bisector
        double theta = 4 * std::atan(bulge), c = norm(q - p), h = c / (2 * std::tan(theta / 2));
        Vec2 mid = (p + q) / 2, n_left = perp((q - p) / c);
        segs.push_back(make_arc_segment(p, mid + n_left * h, theta));
        segs.back().to = q;
      }
    }
    verts_.clear();
  }

 private:
  bool take() {
    if (o_.layer && getAttributes().getLayer() != *o_.layer) return false;
    return true;
  }
  void refuse(const char* kind) {
    if (take()) ++refused[kind];
  }
  // entities whose extrusion direction points down (0, 0, -1) are drawn mirrored in x
  bool mirrored() {
    const DL_Extrusion* e = getExtrusion();
    return e && e->getDirection()[2] < 0;
  }
  Vec2 pt(double x, double y) { return Vec2{mirrored() ? -x : x, y} * o_.unit_m; }
  void arc(double cx, double cy, double r, double a1, double sweep) {
    if (!(r > 0)) return;
    const bool m = mirrored();
    if (m) {  // x -> -x: an angle a becomes pi - a and the direction reverses
      a1 = std::numbers::pi - a1;
      sweep = -sweep;
    }
    Vec2 c = Vec2{m ? -cx : cx, cy} * o_.unit_m;
    Vec2 from = c + Vec2{std::cos(a1), std::sin(a1)} * (r * o_.unit_m);
    segs.push_back(make_arc_segment(from, c, sweep));
  }

  const DxfOptions& o_;
  bool in_poly_ = false, poly_closed_ = false;
  std::vector<DL_VertexData> verts_;
};

PathSegment reversed(PathSegment s) {
  std::swap(s.from, s.to);
  s.sweep = -s.sweep;
  return s;
}

}  // namespace

DxfPath read_dxf_path(const std::string& path, const DxfOptions& opt) {
  {
    std::ifstream probe(path);
    if (!probe) throw InputError("cannot open the DXF file", path);
  }
  Collector col(opt);
  DL_Dxf dxf;
  if (!dxf.in(path, &col)) throw InputError("not a readable DXF file", path);
  col.flush_polyline();
  if (!col.refused.empty()) {
    std::string kinds;
    for (const auto& [k, n] : col.refused) kinds += (kinds.empty() ? "" : ", ") + std::to_string(n) + " " + k;
    throw InputError("unsupported entities (" + kinds +
                     "); polarcam reads LINE, ARC, CIRCLE and POLYLINE/LWPOLYLINE: convert curves to polylines", path);
  }
  std::vector<PathSegment>& all = col.segs;
  if (all.empty())
    throw InputError("no LINE, ARC, CIRCLE or POLYLINE entities" + (opt.layer ? " on layer '" + *opt.layer + "'" : ""), path);

  // chain the pieces end to end, in any order and direction
  const double tol = opt.join_tolerance * opt.unit_m;
  std::vector<bool> used(all.size(), false);
  std::vector<PathSegment> chain{all[0]};
  used[0] = true;
  size_t n_used = 1;
  for (bool grew = true; grew;) {
    grew = false;
    for (size_t i = 0; i < all.size(); ++i) {
      if (used[i]) continue;
      const Vec2 head = chain.front().from, tail = chain.back().to;
      if (norm(chain.back().to - chain.front().from) <= tol && chain.size() > 1) break;  // closed already
      PathSegment s = all[i];
      if (norm(s.from - tail) <= tol) {
        chain.push_back(s);
      } else if (norm(s.to - tail) <= tol) {
        chain.push_back(reversed(s));
      } else if (norm(s.to - head) <= tol) {
        chain.insert(chain.begin(), s);
      } else if (norm(s.from - head) <= tol) {
        chain.insert(chain.begin(), reversed(s));
      } else {
        continue;
      }
      used[i] = true;
      ++n_used;
      grew = true;
    }
  }
  if (n_used != all.size())
    throw InputError("the drawing holds " + std::to_string(all.size() - n_used) +
                     " entities that do not join the first chain of " + std::to_string(n_used) +
                     "; give 'layer' to pick one contour, or close the gaps", path);
  for (size_t i = 1; i < chain.size(); ++i) chain[i].from = chain[i - 1].to;  // snap joints within tolerance
  DxfPath out;
  out.closed = norm(chain.back().to - chain.front().from) <= tol;
  if (out.closed) chain.back().to = chain.front().from;
  out.entities = all.size();
  out.segments = std::move(chain);
  return out;
}

}  // namespace polarcam
