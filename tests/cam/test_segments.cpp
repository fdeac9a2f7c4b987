// Segment curves (lines, cubic Bezier curves, affine images of unit-circle arcs): derivatives against finite
// differences, the parameter (one unit per segment), affine maps, bounding boxes against closed forms, and what
// make_segment_curve refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/segments.hpp"

namespace tu_cam_test_segments {  // the test files of a program compile together (unity build)

using namespace polarcam;
constexpr double kPi = std::numbers::pi;

namespace {

// A curve of one line, one cubic and one arc of a sheared ellipse, joined end to end.
CurvePtr mixed_curve() {
  std::vector<CurveSegment> s;
  s.push_back(line_segment({0, 0}, {2, 0}));
  s.push_back(cubic_segment({2, 0}, {3, 1}, {3, 2}, {2, 3}));
  // centre (2, 4), columns (1, 0.5) and (0.3, 1): at t = -pi/2 the point is (2 - 0.3, 3)
  Vec2 c{2.3, 4}, ax{1, 0.5}, ay{0.3, 1};
  s.push_back(arc_segment(c, ax, ay, -kPi / 2, kPi / 3));
  return make_segment_curve(s, false, "mixed");
}

bool near(Vec2 a, Vec2 b, double tol) { return norm(a - b) <= tol; }

}  // namespace

TEST(Segments, OneUnitPerSegmentAndBreakpointsAtTheJoints) {
  auto c = mixed_curve();
  EXPECT_EQ(c->u_begin(), 0.0);
  EXPECT_EQ(c->u_end(), 3.0);
  EXPECT_EQ(c->breakpoints(), (std::vector<double>{1.0, 2.0}));
  EXPECT_TRUE(near(c->eval(0.5, 0).p, {1, 0}, 1e-15));
  EXPECT_TRUE(near(c->eval(1.0, 0).p, {2, 0}, 1e-15));
  // the cubic's midpoint by the Bernstein formula: (P0 + 3 P1 + 3 P2 + P3) / 8
  EXPECT_TRUE(near(c->eval(1.5, 0).p, (Vec2{2, 0} + 3 * Vec2{3, 1} + 3 * Vec2{3, 2} + Vec2{2, 3}) / 8.0, 1e-15));
  // the arc at its end angle pi/3
  Vec2 end{2.3 + std::cos(kPi / 3) + 0.3 * std::sin(kPi / 3), 4 + 0.5 * std::cos(kPi / 3) + std::sin(kPi / 3)};
  EXPECT_TRUE(near(c->eval(3.0, 0).p, end, 1e-15));
}

TEST(Segments, DerivativesAgreeWithFiniteDifferencesInsideEverySegment) {
  auto c = mixed_curve();
  const double h = 1e-5;
  for (int k = 0; k < 3; ++k)
    for (double f : {0.1, 0.37, 0.5, 0.81}) {
      double u = k + f;
      CurvePoint p = c->eval(u, 3), a = c->eval(u - h, 3), b = c->eval(u + h, 3);
      EXPECT_TRUE(near((b.p - a.p) / (2 * h), p.d1, 1e-8 * (1 + norm(p.d1)))) << "d1 at " << u;
      EXPECT_TRUE(near((b.d1 - a.d1) / (2 * h), p.d2, 1e-8 * (1 + norm(p.d2)))) << "d2 at " << u;
      EXPECT_TRUE(near((b.d2 - a.d2) / (2 * h), p.d3, 1e-8 * (1 + norm(p.d3)))) << "d3 at " << u;
    }
  // a line has no second derivative, a cubic a constant third
  EXPECT_EQ(c->eval(0.3, 3).d2, (Vec2{0, 0}));
  EXPECT_TRUE(near(c->eval(1.2, 3).d3, 6.0 * (Vec2{2, 3} - 3 * Vec2{3, 2} + 3 * Vec2{3, 1} - Vec2{2, 0}), 1e-14));
}

TEST(Segments, QuadraticIsElevatedToTheCubicItIs) {
  Vec2 q0{0, 0}, q1{1, 2}, q2{3, 0};
  CurveSegment g = quadratic_segment(q0, q1, q2);
  for (double s : {0.0, 0.2, 0.5, 0.9, 1.0}) {
    Vec2 want = (1 - s) * (1 - s) * q0 + 2 * (1 - s) * s * q1 + s * s * q2;
    EXPECT_TRUE(near(g.eval(s, 0).p, want, 1e-15)) << s;
    Vec2 dwant = 2 * (1 - s) * (q1 - q0) + 2 * s * (q2 - q1);
    EXPECT_TRUE(near(g.eval(s, 1).d1, dwant, 1e-14)) << s;
  }
}

TEST(Segments, AffineMapsCarryArcsAndCubicsExactly) {
  auto c = mixed_curve();
  // rotate by 0.7 rad, scale x by 2, shear, translate
  Affine2 m{2 * std::cos(0.7), std::sin(0.7), -std::sin(0.7) + 0.4, std::cos(0.7), 5, -3};
  auto t = transform_curve(c, m);
  ASSERT_NE(curve_segments(*t), nullptr);  // still segments
  EXPECT_EQ(t->u_end(), c->u_end());
  for (double u : {0.0, 0.4, 1.3, 2.0, 2.25, 2.9, 3.0}) {
    CurvePoint a = c->eval(u, 3), b = t->eval(u, 3);
    Vec2 want{m.a * a.p.x + m.c * a.p.y + m.e, m.b * a.p.x + m.d * a.p.y + m.f};
    EXPECT_TRUE(near(b.p, want, 1e-14)) << u;
    EXPECT_TRUE(near(b.d1, Vec2{m.a * a.d1.x + m.c * a.d1.y, m.b * a.d1.x + m.d * a.d1.y}, 1e-13)) << u;
    EXPECT_TRUE(near(b.d3, Vec2{m.a * a.d3.x + m.c * a.d3.y, m.b * a.d3.x + m.d * a.d3.y}, 1e-13)) << u;
  }
  EXPECT_THROW(transform_curve(c, Affine2{1, 2, 2, 4, 0, 0}), InputError);  // singular
}

TEST(Segments, SimilarityScalesLengthAndWorksOnAnyCurve) {
  auto circle = make_circle({0.01, 0.02}, 0.005);  // not a segment curve
  auto moved = transform_curve(circle, 3.0, {1.0, -2.0});
  EXPECT_EQ(curve_segments(*moved), nullptr);
  EXPECT_NEAR(arc_length(*moved, moved->u_begin(), moved->u_end()), 3 * 2 * kPi * 0.005, 1e-14);
  for (double f : {0.0, 0.3, 0.77}) {
    double u = circle->u_begin() + f * (circle->u_end() - circle->u_begin());
    EXPECT_TRUE(near(moved->eval(u, 0).p, 3.0 * circle->eval(u, 0).p + Vec2{1, -2}, 1e-15));
  }
  EXPECT_THROW(transform_curve(circle, 0.0, {0, 0}), InputError);
  EXPECT_THROW(transform_curve(circle, -1.0, {0, 0}), InputError);
  EXPECT_THROW(transform_curve(circle, 2.0, {std::nan(""), 0}), InputError);
}

TEST(Segments, BoundingBoxOfSegmentsIsExact) {
  // the cubic (0,0) (0,1) (1,1) (1,0) peaks at s = 1/2, y = 3/4
  auto cubic = make_segment_curve({cubic_segment({0, 0}, {0, 1}, {1, 1}, {1, 0})}, false, "bump");
  Box b = bounding_box(*cubic);
  EXPECT_DOUBLE_EQ(b.lo.x, 0.0);
  EXPECT_DOUBLE_EQ(b.hi.x, 1.0);
  EXPECT_DOUBLE_EQ(b.lo.y, 0.0);
  EXPECT_NEAR(b.hi.y, 0.75, 1e-15);
  // a unit-circle arc about (5, 5) from t = 0.1 to t = 3.0 passes the top (t = pi/2) only
  auto arc = make_segment_curve({arc_segment({5, 5}, {1, 0}, {0, 1}, 0.1, 3.0)}, false, "arc");
  b = bounding_box(*arc);
  EXPECT_NEAR(b.lo.x, 5 + std::cos(3.0), 1e-15);
  EXPECT_NEAR(b.hi.x, 5 + std::cos(0.1), 1e-15);
  EXPECT_NEAR(b.lo.y, 5 + std::sin(0.1), 1e-15);
  EXPECT_NEAR(b.hi.y, 6.0, 1e-15);
  // the same arc run backwards, and an ellipse rotated by 30 degrees: half-widths sqrt(a^2 cos^2 + b^2 sin^2)
  arc = make_segment_curve({arc_segment({5, 5}, {1, 0}, {0, 1}, 3.0, 0.1)}, false, "arc back");
  EXPECT_NEAR(bounding_box(*arc).hi.y, 6.0, 1e-15);
  double a = 3, bb = 1, ph = kPi / 6;
  auto ell = make_segment_curve({arc_segment({0, 0}, {a * std::cos(ph), a * std::sin(ph)},
                                             {-bb * std::sin(ph), bb * std::cos(ph)}, 0, 2 * kPi)},
                                true, "ellipse");
  b = bounding_box(std::vector<CurvePtr>{ell, cubic});
  double hx = std::sqrt(a * a * std::cos(ph) * std::cos(ph) + bb * bb * std::sin(ph) * std::sin(ph));
  double hy = std::sqrt(a * a * std::sin(ph) * std::sin(ph) + bb * bb * std::cos(ph) * std::cos(ph));
  EXPECT_NEAR(b.lo.x, -hx, 1e-14);
  EXPECT_NEAR(b.hi.x, std::max(hx, 1.0), 1e-14);
  EXPECT_NEAR(b.lo.y, -hy, 1e-14);
  EXPECT_NEAR(b.hi.y, hy, 1e-14);
  EXPECT_THROW(bounding_box(std::vector<CurvePtr>{}), InputError);
}

TEST(Segments, BoundingBoxOfOtherCurvesBySamplingAndRefinement) {
  // a limacon r = b + a cos t: x = r cos t is smallest where dx/dt = 0 inside the loop; its extent in y is found
  // where d/dt (r sin t) = 0, i.e. b cos t + a cos 2t = 0
  const double a = 0.0508, b = 0.0762;
  auto lim = make_limacon(a, b);
  Box box = bounding_box(*lim);
  double cy = (-b + std::sqrt(b * b + 8 * a * a)) / (4 * a);  // cos t at the top
  double ty = std::acos(cy), ymax = (b + a * cy) * std::sin(ty);
  EXPECT_NEAR(box.hi.y, ymax, 1e-13);
  EXPECT_NEAR(box.lo.y, -ymax, 1e-13);
  EXPECT_NEAR(box.hi.x, a + b, 1e-13);
  // x = (b + a cos t) cos t is smallest where cos t = -b / (2a) (here inside [-1, 1])
  double cx = -b / (2 * a), xmin = (b + a * cx) * cx;
  EXPECT_NEAR(box.lo.x, xmin, 1e-13);
}

TEST(Segments, RefusesGapsDegenerateSegmentsAndFalseClosure) {
  EXPECT_THROW(make_segment_curve({}, false, "empty"), InputError);
  EXPECT_THROW(make_segment_curve({line_segment({0, 0}, {1, 0}), line_segment({1, 0.1}, {2, 0})}, false, "gap"),
               InputError);
  EXPECT_THROW(make_segment_curve({line_segment({1, 1}, {1, 1})}, false, "dot"), InputError);
  EXPECT_THROW(make_segment_curve({cubic_segment({1, 1}, {1, 1}, {1, 1}, {1, 1})}, false, "dot"), InputError);
  EXPECT_THROW(make_segment_curve({arc_segment({0, 0}, {1, 0}, {2, 0}, 0, 1)}, false, "flat"), InputError);
  EXPECT_THROW(make_segment_curve({line_segment({0, 0}, {1, 0}), line_segment({1, 0}, {1, 1})}, true, "open"),
               InputError);
  EXPECT_THROW(make_segment_curve({line_segment({0, 0}, {std::nan(""), 0})}, false, "nan"), InputError);
  // a joint within rounding is accepted and closed exactly
  auto c = make_segment_curve({line_segment({0, 0}, {1, 0}), line_segment({1, 1e-17}, {0, 1}),
                               line_segment({0, 1}, {1e-17, 0})},
                              true, "triangle");
  EXPECT_EQ(c->eval(c->u_end(), 0).p, c->eval(0, 0).p);
  EXPECT_EQ(c->eval(1.0, 0).p, (Vec2{1, 0}));
}

}  // namespace tu_cam_test_segments
