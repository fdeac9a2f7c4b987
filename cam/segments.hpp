#pragma once
// Curves made of exact segments: straight lines, cubic Bezier curves and elliptical arcs, the vocabulary of SVG
// paths (a quadratic Bezier curve is the cubic it equals, by degree elevation). Every segment is kept in a form an
// affine map carries exactly: a line and a cubic by their control points, an elliptical arc as the affine image of
// an arc of the unit circle,
//
//     P(t) = centre + ax cos t + ay sin t,   t from t0 to t1 (either direction),
//
// where ax and ay are the columns of the 2x2 matrix (the images of the unit vectors). A circular arc has ax and ay
// orthogonal and of equal length; a rotated ellipse has them orthogonal; a sheared one need not.
//
// Parameter: ONE UNIT PER SEGMENT. The curve runs over u in [0, n] for n segments; segment k covers [k, k + 1],
// with the local parameter s = u - k in [0, 1] (a line: P0 + s (P1 - P0); a cubic: the Bernstein form in s; an
// arc: t = t0 + s (t1 - t0)). Position and derivatives to order 3 are exact (closed forms); the joints u = 1 ..
// n - 1 are the breakpoints. The parameter is not arc length: arc_length() (cam/curve.hpp) measures it.
#include <string>
#include <vector>

#include "cam/curve.hpp"

namespace polarcam {

// An affine map of the plane, p -> (a x + c y + e, b x + d y + f): SVG's matrix(a b c d e f).
struct Affine2 {
  double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;

  Vec2 apply(Vec2 p) const { return {a * p.x + c * p.y + e, b * p.x + d * p.y + f}; }
  Vec2 linear(Vec2 v) const { return {a * v.x + c * v.y, b * v.x + d * v.y}; }  // a vector: no translation
  double det() const { return a * d - b * c; }
  // The map `o` first, then this one.
  Affine2 operator*(const Affine2& o) const {
    return {a * o.a + c * o.b, b * o.a + d * o.b, a * o.c + c * o.d, b * o.c + d * o.d, a * o.e + c * o.f + e,
            b * o.e + d * o.f + f};
  }
  static Affine2 translate(double tx, double ty) { return {1, 0, 0, 1, tx, ty}; }
  static Affine2 scale(double sx, double sy) { return {sx, 0, 0, sy, 0, 0}; }
};

struct CurveSegment {
  enum class Kind { line, cubic, arc } kind = Kind::line;
  Vec2 p[4];            // line: p[0] -> p[1]; cubic: the control points p[0] .. p[3]
  Vec2 center, ax, ay;  // arc: centre + ax cos t + ay sin t
  double t0 = 0, t1 = 0;  // arc: the angles it runs between, t0 -> t1

  Vec2 start() const;
  Vec2 end() const;
  // Position and derivatives with respect to the local parameter s in [0, 1], up to `order` (0..3).
  CurvePoint eval(double s, int order) const;
  // The segment under an affine map (exact: control points, centre and columns are mapped).
  CurveSegment transformed(const Affine2& m) const;
};

CurveSegment line_segment(Vec2 a, Vec2 b);
CurveSegment cubic_segment(Vec2 p0, Vec2 p1, Vec2 p2, Vec2 p3);
// The quadratic Bezier curve with control points q0, q1, q2 as the cubic it is: p1 = q0 + 2/3 (q1 - q0),
// p2 = q2 + 2/3 (q1 - q2).
CurveSegment quadratic_segment(Vec2 q0, Vec2 q1, Vec2 q2);
CurveSegment arc_segment(Vec2 center, Vec2 ax, Vec2 ay, double t0, double t1);

// SVG's elliptical arc from `from` to `to` (radii rx, ry, the x axis rotated by `phi` radians, the large-arc and
// sweep flags) converted to its centre form as the SVG 1.1 specification says (Appendix F.6.5, "Conversion from
// endpoint to center parameterization"), with radii too small for the end points scaled up until the ellipse
// just reaches them (F.6.6, "Correction of out-of-range radii"). Negative radii count as their absolute values.
// Adds nothing when the end points coincide and a line when a radius is zero (both as F.6.2 says).
void append_svg_arc(std::vector<CurveSegment>& out, Vec2 from, double rx, double ry, double phi, bool large_arc,
                    bool sweep, Vec2 to);

// A curve of segments (at least one). Each segment must start where the one before ends (within 1e-9 of the
// largest coordinate, the gap then closed by moving the start), must be finite and must move (a line of length
// zero, a cubic with all four points equal or an arc whose matrix is singular or whose angles are equal are
// refused). `closed`: the last segment must end at the first one's start (same tolerance). InputError otherwise,
// naming the segment (counted from 1).
CurvePtr make_segment_curve(std::vector<CurveSegment> segments, bool closed, std::string name);

// The segments of a curve made by make_segment_curve or transform_curve of one, or nullptr.
const std::vector<CurveSegment>* curve_segments(const Curve& c);

// The curve under an affine map, same parameter and breakpoints; derivatives are mapped by the linear part, so
// they stay exact. A segment curve stays a segment curve (its segments mapped exactly). Throws InputError unless
// the map is finite and invertible.
CurvePtr transform_curve(CurvePtr curve, const Affine2& m);
// A similarity without rotation: P -> scale P + offset (scale finite and above zero).
CurvePtr transform_curve(CurvePtr curve, double scale, Vec2 offset);

struct Box {
  Vec2 lo, hi;  // lower left and upper right corners
  double width() const { return hi.x - lo.x; }
  double height() const { return hi.y - lo.y; }
};

// The smallest axis-aligned box holding the curves. Segment curves: exact, from the end points and the interior
// extrema of each coordinate in closed form (a cubic's derivative is a quadratic; an arc's coordinate is
// A cos t + B sin t, extreme at t = atan2(B, A) + k pi). Other curves: 64 samples on each piece between
// breakpoints, every sign change of a coordinate's derivative refined by bisection to the parameter's rounding;
// two extrema of one coordinate closer than a sample spacing may be missed. Throws InputError for an empty set.
Box bounding_box(const std::vector<CurvePtr>& curves);
Box bounding_box(const Curve& curve);

}  // namespace polarcam
