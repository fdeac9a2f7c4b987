// SVG import against hand computations: circles and rounded rectangles against their perimeters, elliptical arcs
// (all four flag combinations, radii scaled up) against their analytic centres, Bezier curves against the Bernstein
// formula, smooth and relative commands, transforms, units, viewBox and preserveAspectRatio, y flipped; what is
// skipped; and every refusal as a one-line InputError naming the file, the line and the element.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "cam/error.hpp"
#include "cam/svg_import.hpp"

namespace tu_cam_test_svg {  // the test files of a program compile together (unity build)

using namespace polarcam;
constexpr double kPi = std::numbers::pi;

namespace {

// A drawing `size` mm square whose user unit is 1 mm, around `body`.
std::string mm_svg(const std::string& body, double size = 200) {
  std::string s = std::to_string(size);
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + s + "mm\" height=\"" + s + "mm\" viewBox=\"0 0 " + s +
         " " + s + "\">\n" + body + "\n</svg>\n";
}
// A user-unit point (x, y) of such a drawing in metres with y up.
Vec2 at_mm(double x, double y, double size = 200) { return {x * 1e-3, (size - y) * 1e-3}; }

SvgDrawing parse(const std::string& text) { return parse_svg(text, "test.svg"); }

double length(const Curve& c) { return arc_length(c, c.u_begin(), c.u_end()); }

bool near(Vec2 a, Vec2 b, double tol) { return norm(a - b) <= tol; }

Vec2 bernstein3(Vec2 p0, Vec2 p1, Vec2 p2, Vec2 p3, double s) {
  double m = 1 - s;
  return m * m * m * p0 + 3 * m * m * s * p1 + 3 * m * s * s * p2 + s * s * s * p3;
}

// The InputError parse throws for `text` (a failure when it throws none).
InputError refusal(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    return e;
  }
  ADD_FAILURE() << "no error for: " << text;
  return InputError("none");
}

std::string data(const std::string& name) {
  return (std::filesystem::path(POLARCAM_SOURCE_DIR) / "tests" / "data" / "svg" / name).string();
}

}  // namespace

TEST(Svg, CircleHasItsLengthAndEveryPointOnIt) {
  SvgDrawing d = parse(mm_svg("<circle id=\"c\" cx=\"50\" cy=\"40\" r=\"10\"/>"));
  ASSERT_EQ(d.contours.size(), 1u);
  const SvgContour& k = d.contours[0];
  EXPECT_EQ(k.id, "c");
  EXPECT_EQ(k.element, "circle");
  EXPECT_TRUE(k.curve->closed());
  EXPECT_NEAR(length(*k.curve), 2 * kPi * 0.01, 1e-9 * 2 * kPi * 0.01);
  Vec2 centre = at_mm(50, 40);
  for (int i = 0; i <= 1000; ++i) {
    double u = k.curve->u_end() * i / 1000.0;
    EXPECT_NEAR(norm(k.curve->eval(u, 0).p - centre), 0.01, 1e-15) << u;
  }
  // arcs, not an approximation
  for (const CurveSegment& g : *curve_segments(*k.curve)) EXPECT_EQ(g.kind, CurveSegment::Kind::arc);
  EXPECT_NEAR(d.width, 0.2, 1e-15);
  EXPECT_NEAR(d.height, 0.2, 1e-15);
}

TEST(Svg, RoundedRectangleHasItsExactPerimeter) {
  // 60 x 30 with corner radius 5 (ry follows rx): 2 (60 + 30) - 8 * 5 + 2 pi 5
  SvgDrawing d = parse(mm_svg("<rect x=\"10\" y=\"20\" width=\"60\" height=\"30\" rx=\"5\"/>"
                              "<rect x=\"100\" y=\"100\" width=\"20\" height=\"20\" ry=\"15\"/>"
                              "<rect x=\"10\" y=\"100\" width=\"40\" height=\"20\"/>"));
  ASSERT_EQ(d.contours.size(), 3u);
  EXPECT_NEAR(length(*d.contours[0].curve), (2 * (60 + 30) - 8 * 5 + 2 * kPi * 5) * 1e-3, 1e-15);
  // a radius over half the side is cut to half of it: the square becomes the circle of radius 10
  EXPECT_NEAR(length(*d.contours[1].curve), 2 * kPi * 10e-3, 1e-15);
  for (double f : {0.1, 0.33, 0.5, 0.9}) {
    const Curve& c = *d.contours[1].curve;
    EXPECT_NEAR(norm(c.eval(c.u_end() * f, 0).p - at_mm(110, 110)), 10e-3, 1e-15);
  }
  EXPECT_NEAR(length(*d.contours[2].curve), 120e-3, 1e-15);
  for (const auto& k : d.contours) EXPECT_TRUE(k.curve->closed());
  // the corners of the sharp one, counter-clockwise from the top left once y is flipped
  const Curve& r = *d.contours[2].curve;
  EXPECT_TRUE(near(r.eval(0, 0).p, at_mm(10, 100), 1e-15));
  EXPECT_TRUE(near(r.eval(1, 0).p, at_mm(50, 100), 1e-15));
  EXPECT_TRUE(near(r.eval(2, 0).p, at_mm(50, 120), 1e-15));
}

TEST(Svg, EllipticalArcsFindTheirAnalyticCentres) {
  // chord from (40, 50) to (60, 50), radius 12.5: the centres lie 7.5 off the chord's middle, (50, 42.5) and
  // (50, 57.5). Sweep 1 runs the angle up (in SVG's axes, y down), large-arc picks the arc over 180 degrees; the
  // small arc turning the angle up is about the lower centre (50, 57.5).
  const double r = 12.5;
  struct Case {
    int large, sweep;
    Vec2 centre;
  } cases[] = {{0, 1, {50, 57.5}}, {1, 1, {50, 42.5}}, {0, 0, {50, 42.5}}, {1, 0, {50, 57.5}}};
  for (const Case& c : cases) {
    std::string d = "M 40 50 A 12.5 12.5 0 " + std::to_string(c.large) + " " + std::to_string(c.sweep) + " 60 50";
    SvgDrawing g = parse(mm_svg("<path d=\"" + d + "\"/>"));
    ASSERT_EQ(g.contours.size(), 1u) << d;
    const Curve& k = *g.contours[0].curve;
    EXPECT_FALSE(k.closed());
    double a0 = std::atan2(50 - c.centre.y, 40 - c.centre.x), a1 = std::atan2(50 - c.centre.y, 60 - c.centre.x);
    double delta = a1 - a0;  // the turn from start to end in the sweep's sense
    if (c.sweep && delta < 0) delta += 2 * kPi;
    if (!c.sweep && delta > 0) delta -= 2 * kPi;
    EXPECT_EQ(std::abs(delta) > kPi, c.large == 1) << d;
    EXPECT_NEAR(length(k), r * std::abs(delta) * 1e-3, 1e-15) << d;
    Vec2 centre = at_mm(c.centre.x, c.centre.y);
    for (double f : {0.0, 0.25, 0.5, 0.75, 1.0})
      EXPECT_NEAR(norm(k.eval(k.u_end() * f, 0).p - centre), r * 1e-3, 1e-15) << d;
    double mid = a0 + delta / 2;
    EXPECT_TRUE(near(k.eval(0.5, 0).p, at_mm(c.centre.x + r * std::cos(mid), c.centre.y + r * std::sin(mid)), 1e-15))
        << d;
    EXPECT_TRUE(near(k.eval(1.0, 0).p, at_mm(60, 50), 1e-15)) << d;
  }
}

TEST(Svg, ArcRadiiTooSmallAreScaledUpAsTheSpecificationSays) {
  // radius 5 for a chord of 20: scaled to 10, a half circle about the chord's middle (50, 50); sweep 1 from the
  // angle 180 degrees up to 360 passes 270 degrees, the point (50, 40)
  SvgDrawing g = parse(mm_svg("<path d=\"M 40 50 A 5 5 0 0 1 60 50\"/>"
                              "<path d=\"M 40 150 A 5 2.5 0 1 0 60 150\"/>"));
  const Curve& circ = *g.contours[0].curve;
  EXPECT_NEAR(length(circ), kPi * 10e-3, 1e-15);
  EXPECT_TRUE(near(circ.eval(0.5, 0).p, at_mm(50, 40), 1e-15));
  // an ellipse 5 x 2.5: lambda = 10^2 / 5^2 = 4, radii doubled to 10 x 5; sweep 0 from 180 degrees down to 0
  // passes 90 degrees, the point (50, 150 + 5)
  const Curve& ell = *g.contours[1].curve;
  EXPECT_TRUE(near(ell.eval(0.5, 0).p, at_mm(50, 155), 1e-15));
  EXPECT_TRUE(near(ell.eval(0.25, 0).p, at_mm(50 + 10 * std::cos(3 * kPi / 4), 150 + 5 * std::sin(3 * kPi / 4)), 1e-15));
  // a rotated ellipse (x axis at 30 degrees), end points on it: the arc goes through its own vertices
  const double ph = kPi / 6, a = 20, b = 8;
  auto pt = [&](double t) {
    return Vec2{100 + a * std::cos(t) * std::cos(ph) - b * std::sin(t) * std::sin(ph),
                100 + a * std::cos(t) * std::sin(ph) + b * std::sin(t) * std::cos(ph)};
  };
  Vec2 s = pt(0.2), e = pt(2.9);
  std::string d = "M " + std::to_string(s.x) + " " + std::to_string(s.y) + " A 20 8 30 0 1 " + std::to_string(e.x) +
                  " " + std::to_string(e.y);
  SvgDrawing rd = parse(mm_svg("<path d=\"" + d + "\"/>"));
  const Curve& rot = *rd.contours[0].curve;
  Vec2 m = pt(0.2 + 2.7 / 2);
  EXPECT_TRUE(near(rot.eval(0.5, 0).p, at_mm(m.x, m.y), 1e-8));  // the end points were printed to 6 decimals
}

TEST(Svg, BezierCurvesFollowTheBernsteinFormula) {
  SvgDrawing g = parse(mm_svg("<path d=\"M 10 80 C 40 10 65 10 95 80\"/><path d=\"M 10 180 Q 52.5 110 95 180\"/>"));
  ASSERT_EQ(g.contours.size(), 2u);
  for (double s : {0.0, 0.1, 0.25, 0.5, 0.8, 1.0}) {
    Vec2 want = bernstein3({10, 80}, {40, 10}, {65, 10}, {95, 80}, s);
    EXPECT_TRUE(near(g.contours[0].curve->eval(s, 0).p, at_mm(want.x, want.y), 1e-15)) << s;
    Vec2 q0{10, 180}, q1{52.5, 110}, q2{95, 180};
    Vec2 wq = (1 - s) * (1 - s) * q0 + 2 * (1 - s) * s * q1 + s * s * q2;
    EXPECT_TRUE(near(g.contours[1].curve->eval(s, 0).p, at_mm(wq.x, wq.y), 1e-15)) << s;
  }
}

TEST(Svg, SmoothCommandsReflectTheControlPoint) {
  // S: the first control point is (65, 10) reflected about (95, 80), i.e. (125, 150); T likewise (137.5, 150); an S
  // after a line has its first control point at the current point
  SvgDrawing g = parse(mm_svg("<path d=\"M 10 80 C 40 10 65 10 95 80 S 150 150 180 80\"/>"
                              "<path d=\"M 10 180 Q 52.5 110 95 180 T 180 180\"/>"
                              "<path d=\"M 0 0 L 10 0 S 20 10 30 0\"/>"));
  ASSERT_EQ(g.contours.size(), 3u);
  Vec2 q0{95, 180}, q1{137.5, 250}, q2{180, 180};
  for (double s : {0.0, 0.3, 0.5, 0.9}) {
    Vec2 w = bernstein3({95, 80}, {125, 150}, {150, 150}, {180, 80}, s);
    EXPECT_TRUE(near(g.contours[0].curve->eval(1 + s, 0).p, at_mm(w.x, w.y), 1e-15)) << s;
    Vec2 wq = (1 - s) * (1 - s) * q0 + 2 * (1 - s) * s * q1 + s * s * q2;
    EXPECT_TRUE(near(g.contours[1].curve->eval(1 + s, 0).p, at_mm(wq.x, wq.y), 1e-15)) << s;
    Vec2 wl = bernstein3({10, 0}, {10, 0}, {20, 10}, {30, 0}, s);
    EXPECT_TRUE(near(g.contours[2].curve->eval(1 + s, 0).p, at_mm(wl.x, wl.y), 1e-15)) << s;
  }
}

TEST(Svg, RelativeCommandsAddToTheCurrentPoint) {
  SvgDrawing g = parse(mm_svg("<path d=\"m 10 20 l 30 0 v 10 h -30 z m 50 0 c 0 -10 20 -10 20 0 a 10 10 0 0 1 -20 0\"/>"));
  ASSERT_EQ(g.contours.size(), 2u);
  const Curve& r = *g.contours[0].curve;
  EXPECT_TRUE(r.closed());
  EXPECT_EQ(r.u_end(), 4.0);
  Vec2 corners[] = {{10, 20}, {40, 20}, {40, 30}, {10, 30}, {10, 20}};
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(near(r.eval(i, 0).p, at_mm(corners[i].x, corners[i].y), 1e-15)) << i;
  // after z the current point is the subpath's start (10, 20): m 50 0 moves to (60, 20)
  const Curve& c = *g.contours[1].curve;
  EXPECT_TRUE(c.closed());  // the arc ends where the subpath started
  Vec2 w = bernstein3({60, 20}, {60, 10}, {80, 10}, {80, 20}, 0.5);
  EXPECT_TRUE(near(c.eval(0.5, 0).p, at_mm(w.x, w.y), 1e-15));
  // the half circle about (70, 20) from (80, 20) back to (60, 20), sweep 1: through (70, 30)
  EXPECT_TRUE(near(c.eval(1.5, 0).p, at_mm(70, 30), 1e-15));
}

TEST(Svg, ASubpathClosingWithinRoundingIsSnappedNotJoinedByASliver) {
  // 0.1 + 0.2 - 0.3 leaves 5.6e-17 in floating point: Z then adds no closing line, the curve closes exactly
  SvgDrawing g = parse(mm_svg("<path d=\"M 0 0 l 0.1 0 l 0.2 0.3 l -0.3 -0.3 z\"/>"));
  const Curve& c = *g.contours[0].curve;
  EXPECT_TRUE(c.closed());
  EXPECT_EQ(c.u_end(), 3.0);
  EXPECT_EQ(c.eval(3.0, 0).p, c.eval(0.0, 0).p);
  // a real gap is closed by a line
  SvgDrawing h = parse(mm_svg("<path d=\"M 0 0 l 0.1 0 l 0.2 0.3 z\"/>"));
  EXPECT_EQ(h.contours[0].curve->u_end(), 3.0);
  EXPECT_NEAR(length(*h.contours[0].curve), (0.1 + std::hypot(0.2, 0.3) + std::hypot(0.3, 0.3)) * 1e-3, 1e-16);
}

TEST(Svg, EverySubpathIsAContourInDocumentOrder) {
  SvgDrawing g = parse(mm_svg(
      "<path id=\"p\" d=\"M 0 0 L 10 0 L 10 10 Z M 20 0 L 30 0 M 40 0 L 50 0 L 50 10 L 40 0 M 90 90\"/>\n"
      "<g><line id=\"l\" x1=\"0\" y1=\"50\" x2=\"10\" y2=\"50\"/></g>\n"
      "<polyline points=\"0 60 10 60 10 70\"/><polygon id=\"t\" points=\"0,80 10,80 5,90\"/>"));
  ASSERT_EQ(g.contours.size(), 6u);
  EXPECT_TRUE(g.contours[0].curve->closed());   // Z
  EXPECT_FALSE(g.contours[1].curve->closed());  // open
  EXPECT_TRUE(g.contours[2].curve->closed());   // ends at its start
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(g.contours[i].id, "p");
    EXPECT_EQ(g.contours[i].subpath, i);
    EXPECT_EQ(g.contours[i].line, 2);
  }
  EXPECT_EQ(g.contours[3].id, "l");
  EXPECT_EQ(g.contours[3].line, 3);
  EXPECT_EQ(g.contours[4].element, "polyline");
  EXPECT_FALSE(g.contours[4].curve->closed());
  EXPECT_EQ(g.contours[5].element, "polygon");
  EXPECT_TRUE(g.contours[5].curve->closed());
  EXPECT_NEAR(length(*g.contours[5].curve), (10 + 2 * std::hypot(5.0, 10.0)) * 1e-3, 1e-15);
}

TEST(Svg, TransformsComposeAsWrittenByHand) {
  // outer: translate(10, 20) rotate(30); inner: scale(2, 3) skewX(20); then the point (1, 1)
  SvgDrawing g = parse(mm_svg("<g transform=\"translate(10,20) rotate(30)\">"
                              "<path transform=\"scale(2 3) skewX(20)\" d=\"M 1 1 L 4 -1\"/></g>"
                              "<path transform=\"rotate(90 50 50)\" d=\"M 60 50 L 70 50\"/>"
                              "<path transform=\"matrix(1 0.5 -0.25 1 100 120) skewY(10)\" d=\"M 2 3 L 4 -1\"/>"));
  ASSERT_EQ(g.contours.size(), 3u);
  auto hand1 = [](double x, double y) {
    double tk = std::tan(20 * kPi / 180);
    double sx = 2 * (x + tk * y), sy = 3 * y;  // skewX, then scale
    double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
    return Vec2{10 + c * sx - s * sy, 20 + s * sx + c * sy};  // rotate, then translate
  };
  Vec2 a = hand1(1, 1), b = hand1(4, -1);
  EXPECT_TRUE(near(g.contours[0].curve->eval(0, 0).p, at_mm(a.x, a.y), 1e-15));
  EXPECT_TRUE(near(g.contours[0].curve->eval(1, 0).p, at_mm(b.x, b.y), 1e-15));
  // a quarter turn about (50, 50) takes (60, 50) to (50, 60) and (70, 50) to (50, 70)
  EXPECT_TRUE(near(g.contours[1].curve->eval(0, 0).p, at_mm(50, 60), 1e-15));
  EXPECT_TRUE(near(g.contours[1].curve->eval(1, 0).p, at_mm(50, 70), 1e-15));
  auto hand3 = [](double x, double y) {
    double ty = y + std::tan(10 * kPi / 180) * x;  // skewY
    return Vec2{1 * x - 0.25 * ty + 100, 0.5 * x + 1 * ty + 120};
  };
  Vec2 c = hand3(2, 3), e = hand3(4, -1);
  EXPECT_TRUE(near(g.contours[2].curve->eval(0, 0).p, at_mm(c.x, c.y), 1e-15));
  EXPECT_TRUE(near(g.contours[2].curve->eval(1, 0).p, at_mm(e.x, e.y), 1e-15));
}

TEST(Svg, ArcsStayExactUnderTransforms) {
  // a circle of radius 10 scaled by (2, 1) and turned 45 degrees: an ellipse with semi-axes 20 and 10 along the
  // diagonals; every point satisfies its equation
  SvgDrawing g = parse(mm_svg("<circle transform=\"translate(100 100) rotate(45) scale(2 1)\" r=\"10\"/>"));
  const Curve& k = *g.contours[0].curve;
  Vec2 c = at_mm(100, 100);
  for (int i = 0; i <= 200; ++i) {
    Vec2 p = (k.eval(k.u_end() * i / 200.0, 0).p - c) * 1e3;  // mm about the centre, y up
    // y is flipped, so the diagonal the major axis lies on is x = -y
    double along = (p.x - p.y) / std::sqrt(2.0), across = (p.x + p.y) / std::sqrt(2.0);
    EXPECT_NEAR(along * along / 400 + across * across / 100, 1.0, 1e-13) << i;
  }
}

TEST(Svg, ViewBoxAndUnitsGiveThePhysicalSize) {
  // 100 mm wide for 200 user units: 1 user unit is 0.5 mm
  SvgDrawing g = parse("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100mm\" height=\"50mm\" viewBox=\"0 0 200 100\">"
                       "<line x1=\"20\" y1=\"10\" x2=\"200\" y2=\"100\"/></svg>");
  EXPECT_NEAR(g.width, 0.1, 1e-15);
  EXPECT_NEAR(g.height, 0.05, 1e-15);
  EXPECT_TRUE(near(g.contours[0].curve->eval(0, 0).p, {0.010, 0.045}, 1e-15));
  EXPECT_TRUE(near(g.contours[0].curve->eval(1, 0).p, {0.100, 0.0}, 1e-15));
  // the absolute units, in a drawing whose user unit is the px (no viewBox): each is one inch
  for (const char* w : {"1in", "2.54cm", "25.4mm", "72pt", "6pc", "96px", "96"}) {
    SvgDrawing u = parse(std::string("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10in\" height=\"960\">"
                                     "<rect width=\"") + w + "\" height=\"" + w + "\"/></svg>");
    EXPECT_NEAR(u.height, 0.254, 1e-15) << w;
    EXPECT_NEAR(length(*u.contours[0].curve), 4 * 0.0254, 1e-15) << w;
    EXPECT_TRUE(near(u.contours[0].curve->eval(1, 0).p, {0.0254, 0.254}, 1e-15)) << w;
  }
  // no width or height: user units are px, the size that of the viewBox
  SvgDrawing px = parse("<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"10 0 96 48\"><line x1=\"10\" y1=\"48\" "
                        "x2=\"106\" y2=\"0\"/></svg>");
  EXPECT_NEAR(px.width, 0.0254, 1e-15);
  EXPECT_NEAR(px.height, 0.0127, 1e-15);
  EXPECT_TRUE(near(px.contours[0].curve->eval(1, 0).p, {0.0254, 0.0127}, 1e-15));
  // only a width: the height follows from the viewBox's aspect
  SvgDrawing w_only = parse("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100mm\" viewBox=\"0 0 200 100\">"
                            "<line x1=\"0\" y1=\"0\" x2=\"10\" y2=\"0\"/></svg>");
  EXPECT_NEAR(w_only.height, 0.05, 1e-15);
  EXPECT_TRUE(near(w_only.contours[0].curve->eval(0, 0).p, {0, 0.05}, 1e-15));
}

TEST(Svg, PreserveAspectRatioPlacesTheViewBox) {
  // a 100 x 100 mm viewport for a 200 x 100 viewBox
  auto first_point = [](const std::string& par, double x, double y) {
    std::string p = par.empty() ? "" : " preserveAspectRatio=\"" + par + "\"";
    SvgDrawing g = parse("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100mm\" height=\"100mm\" viewBox=\"0 0 200 "
                         "100\"" + p + "><path d=\"M " + std::to_string(x) + " " + std::to_string(y) + " l 1 0\"/></svg>");
    return g.contours[0].curve->eval(0, 0).p;
  };
  // default xMidYMid meet: scale 0.5 mm, 25 mm of room above and below; (0, 0) sits 25 mm from the top
  EXPECT_TRUE(near(first_point("", 0, 0), {0, 0.075}, 1e-15));
  EXPECT_TRUE(near(first_point("xMidYMid meet", 200, 100), {0.1, 0.025}, 1e-15));
  EXPECT_TRUE(near(first_point("xMinYMin", 0, 0), {0, 0.1}, 1e-15));
  EXPECT_TRUE(near(first_point("xMaxYMax meet", 0, 0), {0, 0.05}, 1e-15));
  // none: 0.5 mm across, 1 mm down
  EXPECT_TRUE(near(first_point("none", 100, 50), {0.05, 0.05}, 1e-15));
  // slice: scale 1 mm, the viewBox overhangs by 100 mm; xMaxYMax puts its right edge on the viewport's
  EXPECT_TRUE(near(first_point("xMaxYMax slice", 150, 50), {0.05, 0.05}, 1e-15));
  EXPECT_TRUE(near(first_point("xMidYMid slice", 100, 0), {0.05, 0.1}, 1e-15));
}

TEST(Svg, YIsFlippedAboutTheDrawingsHeight) {
  SvgDrawing g = parse(mm_svg("<line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"10\"/>", 10));
  EXPECT_TRUE(near(g.contours[0].curve->eval(0, 0).p, {0, 0.010}, 1e-15));  // the top edge
  EXPECT_TRUE(near(g.contours[0].curve->eval(1, 0).p, {0, 0}, 1e-15));      // the bottom edge
  // the drawing keeps its look: an arc from left to right over the top (sweep 1) turns clockwise here too
  SvgDrawing s = parse(mm_svg("<path d=\"M 40 50 A 10 10 0 0 1 60 50\"/>"));
  EXPECT_LT(curvature(s.contours[0].curve->eval(0.5, 2)), 0.0);
  // without any size the top edge is y = 0
  SvgDrawing n = parse("<svg xmlns=\"http://www.w3.org/2000/svg\"><line x1=\"0\" y1=\"96\" x2=\"96\" y2=\"96\"/></svg>");
  EXPECT_EQ(n.height, 0.0);
  EXPECT_TRUE(near(n.contours[0].curve->eval(0, 0).p, {0, -0.0254}, 1e-15));
}

TEST(Svg, InvisibleAndNonGeometricElementsAreSkipped) {
  SvgDrawing g = parse(mm_svg(
      "<defs><path id=\"shape\" d=\"M 0 0 L 10 0\"/><g id=\"pair\"><circle r=\"1\"/><circle cx=\"5\" r=\"1\"/></g></defs>"
      "<text x=\"0\" y=\"10\">PC</text><image href=\"x.png\" width=\"10\" height=\"10\"/>"
      "<path display=\"none\" d=\"M 0 0 L 1 1\"/><path style=\"fill:red;display:none\" d=\"M 0 0 L 1 1\"/>"
      "<g style=\"display: none\"><path d=\"M 0 0 L 1 1\"/></g>"
      "<metadata><foo xmlns=\"urn:x\">bar</foo></metadata>"
      "<path id=\"seen\" data-x=\"1\" d=\"M 0 0 L 1 0\"/>"
      "<switch><foreignObject requiredExtensions=\"urn:x\" width=\"1\" height=\"1\"/><g><path id=\"chosen\" "
      "d=\"M 0 0 L 2 0\"/></g><path id=\"other\" d=\"M 0 0 L 3 0\"/></switch>"
      "<use href=\"#shape\" x=\"100\" y=\"100\"/><use xmlns:xlink=\"http://www.w3.org/1999/xlink\" "
      "xlink:href=\"#pair\" transform=\"translate(50 0)\" y=\"20\"/>"));
  ASSERT_EQ(g.contours.size(), 5u);
  EXPECT_EQ(g.contours[0].id, "seen");
  EXPECT_EQ(g.contours[1].id, "chosen");  // the first child of <switch> without a condition
  EXPECT_EQ(g.contours[2].id, "shape");   // drawn by the <use>, moved by its x and y
  EXPECT_TRUE(near(g.contours[2].curve->eval(0, 0).p, at_mm(100, 100), 1e-15));
  EXPECT_TRUE(near(g.contours[2].curve->eval(1, 0).p, at_mm(110, 100), 1e-15));
  // the group's two circles, moved by the transform and then y = 20
  Vec2 c2 = (g.contours[4].curve->eval(0, 0).p + g.contours[4].curve->eval(1, 0).p) * 0.5;
  EXPECT_TRUE(near(c2, at_mm(55, 20), 1e-15));
}

TEST(Svg, ExampleLogoImportsCleanly) {
  SvgDrawing g = read_svg(std::string(POLARCAM_SOURCE_DIR) + "/examples/patterns/logo.svg");
  ASSERT_GE(g.contours.size(), 3u);
  Box b = bounding_box([&] {
    std::vector<CurvePtr> v;
    for (const auto& k : g.contours) v.push_back(k.curve);
    return v;
  }());
  EXPECT_GE(b.lo.x, 0.0);
  EXPECT_GE(b.lo.y, 0.0);
  EXPECT_LE(b.hi.x, g.width);
  EXPECT_LE(b.hi.y, g.height);
  for (const auto& k : g.contours) EXPECT_GT(length(*k.curve), 0.0);
}

TEST(Svg, FilesFromTheTestDataRead) {
  SvgDrawing g = read_svg(data("shapes.svg"));
  ASSERT_EQ(g.contours.size(), 4u);
  EXPECT_EQ(g.contours[0].id, "ring");
  EXPECT_NEAR(length(*g.contours[0].curve), 2 * kPi * 0.02, 1e-15);
}

TEST(Svg, RefusalsAreOneLineNamingFileLineAndElement) {
  struct Case {
    std::string text, place, words;
  } cases[] = {
      {"<svg xmlns=\"http://www.w3.org/2000/svg\"><path", "test.svg:1", "not XML"},
      {"hello", "test.svg:1", "not XML"},
      {"<html/>", "test.svg:1", "root element is <html>"},
      {"<svg><path d=\"M 0 0 L 1 1\"/></svg>", "test.svg:1", "xmlns"},
      {mm_svg("<path id=\"bad\" d=\"M 10 L\"/>"), "test.svg:2", "<path id=\"bad\">: its attribute \"d\" cannot be read (\"M 10 L\")"},
      {mm_svg("<g>\n<path d=\"M 0 0 L nan 5\"/></g>"), "test.svg:3", "<path>"},
      {mm_svg("<path d=\"M 0 0 L 1e999 5\"/>"), "test.svg:2", "<path>"},
      {mm_svg("<rect width=\"-5\" height=\"3\"/>"), "test.svg:2", "negative"},
      {mm_svg("<circle id=\"c\" r=\"x\"/>"), "test.svg:2", "<circle id=\"c\">"},
      {"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10mm\" height=\"10mm\" viewBox=\"0 0 0 10\"><path d=\"M 0 0 "
       "L 1 1\"/></svg>",
       "test.svg:1", "viewBox"},
      {"<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 10 -1\"><path d=\"M 0 0 L 1 1\"/></svg>", "test.svg:1",
       "viewBox"},
      {mm_svg("<text>only words</text>"), "test.svg", "no drawable geometry"},
      {mm_svg("<path d=\"M 0 0\" display=\"none\"/>"), "test.svg", "no drawable geometry"},
      {mm_svg("<symbol id=\"s\"><path d=\"M 0 0 L 1 1\"/></symbol><use id=\"u\" href=\"#s\"/>"), "test.svg:2",
       "<use id=\"u\">: draws a <symbol>"},
      {mm_svg("<use href=\"#nowhere\"/>"), "test.svg:2", "not in the file"},
      {mm_svg("<use href=\"other.svg#a\"/>"), "test.svg:2", "outside this file"},
      {mm_svg("<g id=\"loop\"><use href=\"#loop\"/></g>"), "test.svg:2", "itself"},
      {mm_svg("<path id=\"empty\"/>"), "test.svg:2", "<path id=\"empty\">: lacks its attribute \"d\""},
      // numbers no machine draws: named by the element (they were scaled onto the table by a factor that rounded to
      // nothing, and refused as a singular transform naming no file)
      {mm_svg("<path id=\"far\" d=\"M 0 0 L 1e300 1e300\"/>"), "test.svg:2", "<path id=\"far\">: subpath 1 reaches 1e+297 m"},
      {mm_svg("<g transform=\"scale(1e200)\">\n<path d=\"M 0 0 L 1 1\"/></g>"), "test.svg:3", "beyond 1 km"},
  };
  for (const Case& c : cases) {
    InputError e = refusal(c.text);
    EXPECT_EQ(e.place(), c.place) << e.what();
    EXPECT_NE(e.message().find(c.words), std::string::npos) << e.what();
  }
  try {
    read_svg(data("bad_path.svg"));
    ADD_FAILURE() << "read a broken path";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), data("bad_path.svg") + ":5");
    EXPECT_NE(e.message().find("<path id=\"broken\">"), std::string::npos) << e.what();
  }
  try {
    read_svg(data("missing.svg"));
    ADD_FAILURE() << "read a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), data("missing.svg"));
  }
}

}  // namespace tu_cam_test_svg
