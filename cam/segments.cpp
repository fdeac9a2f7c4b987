#include "cam/segments.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "cam/error.hpp"

namespace polarcam {
namespace {

bool finite(Vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }
double coord(Vec2 v, int i) { return i == 0 ? v.x : v.y; }

// ---- bounding boxes ----------------------------------------------------------------------------------------------

struct BoxAcc {
  Vec2 lo{HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL};
  void add(Vec2 p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
  }
};

void add_segment_extent(const CurveSegment& g, BoxAcc& box) {
  box.add(g.start());
  box.add(g.end());
  switch (g.kind) {
    case CurveSegment::Kind::line: return;
    case CurveSegment::Kind::cubic:
      for (int i = 0; i < 2; ++i) {
        // B'(s) / 3 = d0 + 2 s (d1 - d0) + s^2 (d0 - 2 d1 + d2)
        double d0 = coord(g.p[1] - g.p[0], i), d1 = coord(g.p[2] - g.p[1], i), d2 = coord(g.p[3] - g.p[2], i);
        double qa = d0 - 2 * d1 + d2, qb = 2 * (d1 - d0), qc = d0;
        double roots[2];
        int n = 0;
        if (qa == 0.0) {
          if (qb != 0.0) roots[n++] = -qc / qb;
        } else {
          double disc = qb * qb - 4 * qa * qc;
          if (disc >= 0.0) {
            // the numerically stable pair of roots
            double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
            roots[n++] = q / qa;
            if (q != 0.0) roots[n++] = qc / q;
          }
        }
        for (int k = 0; k < n; ++k)
          if (roots[k] > 0.0 && roots[k] < 1.0) box.add(g.eval(roots[k], 0).p);
      }
      return;
    case CurveSegment::Kind::arc: {
      double tmin = std::min(g.t0, g.t1), tmax = std::max(g.t0, g.t1);
      for (int i = 0; i < 2; ++i) {
        // coordinate = centre + A cos t + B sin t, extreme where -A sin t + B cos t = 0
        double t_star = std::atan2(coord(g.ay, i), coord(g.ax, i));
        double k0 = std::ceil((tmin - t_star) / std::numbers::pi), k1 = std::floor((tmax - t_star) / std::numbers::pi);
        for (double k = k0; k <= k1; k += 1.0) {
          double t = t_star + k * std::numbers::pi;
          box.add(g.center + g.ax * std::cos(t) + g.ay * std::sin(t));
        }
      }
      return;
    }
  }
}

// A curve we cannot read in closed form: samples, and every sign change of a coordinate's derivative refined by
// bisection.
void add_sampled_extent(const Curve& c, BoxAcc& box) {
  std::vector<double> cuts{c.u_begin()};
  for (double b : c.breakpoints()) cuts.push_back(b);
  cuts.push_back(c.u_end());
  constexpr int kSamples = 64;
  for (size_t piece = 0; piece + 1 < cuts.size(); ++piece) {
    double ua = cuts[piece], ub = cuts[piece + 1];
    if (!(ub > ua)) continue;
    // evaluate just inside the piece so that a one-sided derivative belongs to it
    CurvePoint prev = c.eval(ua, 1);
    box.add(prev.p);
    double u_prev = ua;
    for (int k = 1; k <= kSamples; ++k) {
      double u = k == kSamples ? ub : ua + (ub - ua) * k / kSamples;
      CurvePoint cur = c.eval(u, 1);
      box.add(cur.p);
      for (int i = 0; i < 2; ++i) {
        double da = coord(prev.d1, i), db = coord(cur.d1, i);
        if (!((da > 0 && db < 0) || (da < 0 && db > 0))) continue;
        double lo = u_prev, hi = u;
        for (int it = 0; it < 200 && hi - lo > 0; ++it) {
          double mid = 0.5 * (lo + hi);
          if (mid <= lo || mid >= hi) break;
          double dm = coord(c.eval(mid, 1).d1, i);
          if ((dm > 0) == (da > 0) && dm != 0) lo = mid;
          else hi = mid;
        }
        box.add(c.eval(lo, 0).p);
        box.add(c.eval(hi, 0).p);
      }
      prev = cur;
      u_prev = u;
    }
  }
}

// ---- the curve ---------------------------------------------------------------------------------------------------

class SegmentCurve final : public Curve {
 public:
  SegmentCurve(std::vector<CurveSegment> segs, bool closed, std::string name)
      : Curve(0.0, static_cast<double>(segs.size()), closed, std::move(name)), segs_(std::move(segs)) {}

  CurvePoint eval(double u, int order) const override {
    double k = std::floor(u);
    k = std::clamp(k, 0.0, static_cast<double>(segs_.size() - 1));
    return segs_[static_cast<size_t>(k)].eval(u - k, order);
  }

  std::vector<double> breakpoints() const override {
    std::vector<double> b;
    for (size_t k = 1; k < segs_.size(); ++k) b.push_back(static_cast<double>(k));
    return b;
  }

  const std::vector<CurveSegment>& segments() const { return segs_; }

 private:
  std::vector<CurveSegment> segs_;
};

// Any curve under an affine map.
class MappedCurve final : public Curve {
 public:
  MappedCurve(CurvePtr c, const Affine2& m, std::string name)
      : Curve(c->u_begin(), c->u_end(), c->closed(), std::move(name)), c_(std::move(c)), m_(m) {}
  CurvePoint eval(double u, int order) const override {
    CurvePoint p = c_->eval(u, order);
    return {m_.apply(p.p), m_.linear(p.d1), m_.linear(p.d2), m_.linear(p.d3)};
  }
  std::vector<double> breakpoints() const override { return c_->breakpoints(); }
  double rounding_scale() const override {
    double norm_m = std::abs(m_.a) + std::abs(m_.b) + std::abs(m_.c) + std::abs(m_.d);
    return norm_m * c_->rounding_scale() + std::abs(m_.e) + std::abs(m_.f);
  }

 private:
  CurvePtr c_;
  Affine2 m_;
};

std::string seg_name(size_t i) { return "segment " + std::to_string(i + 1); }

}  // namespace

// ---- segments ----------------------------------------------------------------------------------------------------

Vec2 CurveSegment::start() const {
  if (kind == Kind::arc) return center + ax * std::cos(t0) + ay * std::sin(t0);
  return p[0];
}

Vec2 CurveSegment::end() const {
  switch (kind) {
    case Kind::line: return p[1];
    case Kind::cubic: return p[3];
    case Kind::arc: return center + ax * std::cos(t1) + ay * std::sin(t1);
  }
  return p[1];
}

CurvePoint CurveSegment::eval(double s, int order) const {
  CurvePoint r;
  switch (kind) {
    case Kind::line:
      r.p = p[0] + (p[1] - p[0]) * s;
      if (order >= 1) r.d1 = p[1] - p[0];
      return r;
    case Kind::cubic: {
      double m = 1.0 - s;
      r.p = p[0] * (m * m * m) + p[1] * (3 * m * m * s) + p[2] * (3 * m * s * s) + p[3] * (s * s * s);
      if (order >= 1) r.d1 = ((p[1] - p[0]) * (m * m) + (p[2] - p[1]) * (2 * m * s) + (p[3] - p[2]) * (s * s)) * 3.0;
      if (order >= 2) r.d2 = ((p[2] - p[1] * 2.0 + p[0]) * m + (p[3] - p[2] * 2.0 + p[1]) * s) * 6.0;
      if (order >= 3) r.d3 = (p[3] - p[2] * 3.0 + p[1] * 3.0 - p[0]) * 6.0;
      return r;
    }
    case Kind::arc: {
      double D = t1 - t0, t = t0 + s * D, c = std::cos(t), sn = std::sin(t);
      Vec2 radial = ax * c + ay * sn, tangential = ay * c - ax * sn;
      r.p = center + radial;
      if (order >= 1) r.d1 = tangential * D;
      if (order >= 2) r.d2 = radial * (-D * D);
      if (order >= 3) r.d3 = tangential * (-D * D * D);
      return r;
    }
  }
  return r;
}

CurveSegment CurveSegment::transformed(const Affine2& m) const {
  CurveSegment g = *this;
  for (Vec2& q : g.p) q = m.apply(q);
  g.center = m.apply(center);
  g.ax = m.linear(ax);
  g.ay = m.linear(ay);
  return g;
}

CurveSegment line_segment(Vec2 a, Vec2 b) {
  CurveSegment g;
  g.kind = CurveSegment::Kind::line;
  g.p[0] = a;
  g.p[1] = b;
  return g;
}

CurveSegment cubic_segment(Vec2 p0, Vec2 p1, Vec2 p2, Vec2 p3) {
  CurveSegment g;
  g.kind = CurveSegment::Kind::cubic;
  g.p[0] = p0;
  g.p[1] = p1;
  g.p[2] = p2;
  g.p[3] = p3;
  return g;
}

CurveSegment quadratic_segment(Vec2 q0, Vec2 q1, Vec2 q2) {
  return cubic_segment(q0, q0 + (q1 - q0) * (2.0 / 3.0), q2 + (q1 - q2) * (2.0 / 3.0), q2);
}

CurveSegment arc_segment(Vec2 center, Vec2 ax, Vec2 ay, double t0, double t1) {
  CurveSegment g;
  g.kind = CurveSegment::Kind::arc;
  g.center = center;
  g.ax = ax;
  g.ay = ay;
  g.t0 = t0;
  g.t1 = t1;
  return g;
}

void append_svg_arc(std::vector<CurveSegment>& out, Vec2 from, double rx, double ry, double phi, bool large_arc,
                    bool sweep, Vec2 to) {
  if (from == to) return;  // F.6.2: the arc is omitted
  rx = std::abs(rx);
  ry = std::abs(ry);
  if (rx == 0.0 || ry == 0.0) {  // F.6.2: a straight line
    out.push_back(line_segment(from, to));
    return;
  }
  const double cphi = std::cos(phi), sphi = std::sin(phi);
  // F.6.5.1: the half chord in the ellipse's own axes
  const Vec2 h = (from - to) * 0.5;
  const double x1 = cphi * h.x + sphi * h.y, y1 = -sphi * h.x + cphi * h.y;
  // F.6.6: radii too small are scaled up until the ellipse just reaches both ends
  const double lambda = (x1 * x1) / (rx * rx) + (y1 * y1) / (ry * ry);
  if (lambda > 1.0) {
    const double k = std::sqrt(lambda);
    rx *= k;
    ry *= k;
  }
  // F.6.5.2: the centre in the ellipse's axes; the radicand is zero (rounded either way) when the radii were scaled
  const double rx2 = rx * rx, ry2 = ry * ry, den = rx2 * y1 * y1 + ry2 * x1 * x1;
  double rad = den > 0.0 ? (rx2 * ry2 - den) / den : 0.0;
  double coef = std::sqrt(std::max(0.0, rad));
  if (large_arc == sweep) coef = -coef;
  const double cx1 = coef * rx * y1 / ry, cy1 = -coef * ry * x1 / rx;
  // F.6.5.3: back to the drawing's axes
  const Vec2 mid = (from + to) * 0.5;
  const Vec2 center{cphi * cx1 - sphi * cy1 + mid.x, sphi * cx1 + cphi * cy1 + mid.y};
  // F.6.5.5-6: the start angle and the sweep, on the unit circle the ellipse is the image of
  const double t0 = std::atan2((y1 - cy1) / ry, (x1 - cx1) / rx);
  const double te = std::atan2((-y1 - cy1) / ry, (-x1 - cx1) / rx);
  double dt = te - t0;
  constexpr double two_pi = 2.0 * std::numbers::pi;
  if (sweep && dt <= 0.0) dt += two_pi;
  if (!sweep && dt >= 0.0) dt -= two_pi;
  const Vec2 ax{rx * cphi, rx * sphi}, ay{-ry * sphi, ry * cphi};
  out.push_back(arc_segment(center, ax, ay, t0, t0 + dt));
}

CurvePtr make_segment_curve(std::vector<CurveSegment> segs, bool closed, std::string name) {
  if (segs.empty()) throw InputError("a curve needs at least one segment");
  double size = 0.0;
  for (size_t i = 0; i < segs.size(); ++i) {
    const CurveSegment& g = segs[i];
    bool ok = true;
    if (g.kind == CurveSegment::Kind::arc)
      ok = finite(g.center) && finite(g.ax) && finite(g.ay) && std::isfinite(g.t0) && std::isfinite(g.t1);
    else
      for (int k = 0; k < (g.kind == CurveSegment::Kind::line ? 2 : 4); ++k) ok = ok && finite(g.p[k]);
    if (!ok) throw InputError(seg_name(i) + " has a coordinate that is not a finite number");
    switch (g.kind) {
      case CurveSegment::Kind::line:
        if (g.p[0] == g.p[1]) throw InputError(seg_name(i) + " is a line of length zero");
        break;
      case CurveSegment::Kind::cubic:
        if (g.p[0] == g.p[1] && g.p[1] == g.p[2] && g.p[2] == g.p[3])
          throw InputError(seg_name(i) + " is a cubic whose four points coincide");
        break;
      case CurveSegment::Kind::arc:
        if (cross(g.ax, g.ay) == 0.0) throw InputError(seg_name(i) + " is an arc of a flat ellipse (singular matrix)");
        if (g.t0 == g.t1) throw InputError(seg_name(i) + " is an arc of angle zero");
        break;
    }
    for (Vec2 q : {g.start(), g.end()}) size = std::max({size, std::abs(q.x), std::abs(q.y)});
  }
  const double tol = 1e-9 * size;
  auto joined = [&](size_t next, Vec2 at) {  // moves the start of a line or cubic onto the end before it
    if (segs[next].kind != CurveSegment::Kind::arc) segs[next].p[0] = at;
  };
  for (size_t i = 1; i < segs.size(); ++i) {
    Vec2 at = segs[i - 1].end();
    if (norm(segs[i].start() - at) > tol)
      throw InputError(seg_name(i) + " does not start where " + seg_name(i - 1) + " ends");
    joined(i, at);
  }
  if (closed) {
    CurveSegment& last = segs.back();
    Vec2 first = segs.front().start();
    if (norm(last.end() - first) > tol)
      throw InputError("the curve is declared closed but its last segment does not end at its start");
    if (last.kind == CurveSegment::Kind::line) last.p[1] = first;
    else if (last.kind == CurveSegment::Kind::cubic) last.p[3] = first;
    else if (segs.size() > 1) joined(0, last.end());
  }
  return std::make_shared<SegmentCurve>(std::move(segs), closed, std::move(name));
}

const std::vector<CurveSegment>* curve_segments(const Curve& c) {
  auto* s = dynamic_cast<const SegmentCurve*>(&c);
  return s ? &s->segments() : nullptr;
}

CurvePtr transform_curve(CurvePtr curve, const Affine2& m) {
  for (double v : {m.a, m.b, m.c, m.d, m.e, m.f})
    if (!std::isfinite(v)) throw InputError("a transform of a curve must have finite coefficients");
  if (!(std::abs(m.det()) > 0.0)) throw InputError("a transform of a curve must be invertible (its determinant is 0)");
  if (const auto* segs = curve_segments(*curve)) {
    std::vector<CurveSegment> out;
    out.reserve(segs->size());
    for (const CurveSegment& g : *segs) out.push_back(g.transformed(m));
    return make_segment_curve(std::move(out), curve->closed(), curve->name());
  }
  std::ostringstream os;
  os.precision(10);
  os << curve->name() << " mapped by matrix(" << m.a << ' ' << m.b << ' ' << m.c << ' ' << m.d << ' ' << m.e << ' '
     << m.f << ')';
  return std::make_shared<MappedCurve>(std::move(curve), m, os.str());
}

CurvePtr transform_curve(CurvePtr curve, double scale, Vec2 offset) {
  if (!(scale > 0.0) || !std::isfinite(scale)) throw InputError("a size scale must be a number above zero");
  return transform_curve(std::move(curve), Affine2{scale, 0, 0, scale, offset.x, offset.y});
}

Box bounding_box(const Curve& curve) {
  BoxAcc box;
  if (const auto* segs = curve_segments(curve))
    for (const CurveSegment& g : *segs) add_segment_extent(g, box);
  else
    add_sampled_extent(curve, box);
  return {box.lo, box.hi};
}

Box bounding_box(const std::vector<CurvePtr>& curves) {
  if (curves.empty()) throw InputError("the bounding box of no curves is not defined");
  Box b = bounding_box(*curves.front());
  for (size_t i = 1; i < curves.size(); ++i) {
    Box c = bounding_box(*curves[i]);
    b.lo = {std::min(b.lo.x, c.lo.x), std::min(b.lo.y, c.lo.y)};
    b.hi = {std::max(b.hi.x, c.hi.x), std::max(b.hi.y, c.hi.y)};
  }
  return b;
}

}  // namespace polarcam
