// Contours: analytic derivatives against finite differences, curvature, splines, paths and offsets, expression
// curves against the named ones, point files, and the tool path.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/expr_curves.hpp"
#include "cam/path.hpp"
#include "cam/point_files.hpp"
#include "cam/thr_file.hpp"
#include "cam/spline.hpp"
#include "cam/toolpath.hpp"
#include "tests/temp_path.hpp"

namespace tu_cam_test_cam {  // the test files of a program compile together (unity build)

using namespace polarcam;
constexpr double kPi = std::numbers::pi;

namespace {

// central differences of the next lower order (independent of the analytic derivatives)
void check_derivatives(const Curve& c, int max_order, double tol) {
  const double L = c.u_end() - c.u_begin();
  for (int i = 1; i < 20; ++i) {
    double u = c.u_begin() + L * i / 20.0, h = 1e-5 * L;
    CurvePoint p = c.eval(u, 3), a = c.eval(u - h, 3), b = c.eval(u + h, 3);
    auto fd = [&](Vec2 x, Vec2 y) { return (y - x) / (2 * h); };
    auto close = [&](Vec2 x, Vec2 y, double scale) { return norm(x - y) <= tol * scale; };
    double s1 = norm(p.d1) + 1e-12;
    EXPECT_TRUE(close(fd(a.p, b.p), p.d1, s1)) << c.name() << " d1 at u=" << u;
    if (max_order >= 2) {
      EXPECT_TRUE(close(fd(a.d1, b.d1), p.d2, norm(p.d2) + s1)) << c.name() << " d2 at u=" << u;
    }
    if (max_order >= 3) {
      EXPECT_TRUE(close(fd(a.d2, b.d2), p.d3, norm(p.d3) + norm(p.d2) + s1)) << c.name() << " d3";
    }
  }
}

}  // namespace

TEST(Curves, AnalyticDerivativesMatchFiniteDifferences) {
  for (auto c : {make_circle({0.1, 0.2}, 0.05), make_witch(0.2159, -0.2, 0.2), make_serpentine(0.0127, 0.0762, -0.07, 0.07),
                 make_limacon(0.0508, 0.0762), make_spiral(0.01, 0.005, 0, 20), make_rose(0.05, 3, 1),
                 make_rose(0.05, 2, 3), make_line({0, 0}, {0.1, 0.05})})
    check_derivatives(*c, 3, 1e-6);
}

TEST(Curves, CurvatureOfACircleIsOneOverR) {
  auto c = make_circle({0, 0}, 0.04);
  for (double u = 0; u < 6; u += 0.5) {
    EXPECT_NEAR(curvature(c->eval(u, 2)), 25.0, 1e-12);
    EXPECT_NEAR(curvature_derivative(c->eval(u, 3)), 0.0, 1e-9);
  }
  // limacon: Eq. 3.4 in polar form, rho = (r^2 + r'^2)^(3/2) / (r^2 + 2 r'^2 - r r'')
  const double a = 0.0508, b = 0.0762;
  auto l = make_limacon(a, b);
  for (double t = 0.1; t < 6.2; t += 0.7) {
    double r = b + a * std::cos(t), r1 = -a * std::sin(t), r2 = -a * std::cos(t);
    double rho = std::pow(r * r + r1 * r1, 1.5) / (r * r + 2 * r1 * r1 - r * r2);
    EXPECT_NEAR(1.0 / curvature(l->eval(t, 2)), rho, 1e-12);
  }
}

TEST(Curves, ArcLengthOfKnownCurves) {
  EXPECT_NEAR(arc_length(*make_circle({0, 0}, 0.05), 0, 2 * kPi), 2 * kPi * 0.05, 1e-15);
  EXPECT_NEAR(arc_length(*make_line({0, 0}, {0.3, 0.4}), 0, 0.5), 0.5, 1e-15);
  // Archimedean spiral r = b t: s = b/2 [t sqrt(1+t^2) + asinh t]
  const double b = 0.01, T = 10;
  EXPECT_NEAR(arc_length(*make_spiral(0, b, 0, T), 0, T), b / 2 * (T * std::sqrt(1 + T * T) + std::asinh(T)), 1e-14);
}

// A path that oscillates a billion times over its parameter: its length is refused as too detailed instead of
// being halved towards 2^40 pieces (a polar expression r = 3 + sin(1e9 t) ran without end; found by a sweep of
// hostile inputs). A spiral of two thousand turns is measured all the same, to its closed form.
TEST(Curves, ArcLengthOfAPathTooDetailedToMachineIsRefused) {
  struct Wiggle : Curve {
    Wiggle() : Curve(0.0, 1.0, false, "wiggle") {}
    CurvePoint eval(double u, int order) const override {
      CurvePoint p;
      p.p = {u, 0.01 * std::sin(1e9 * u)};
      if (order >= 1) p.d1 = {1.0, 1e7 * std::cos(1e9 * u)};
      if (order >= 2) p.d2 = {0.0, -1e16 * std::sin(1e9 * u)};
      return p;
    }
  };
  const Wiggle w;
  EXPECT_THROW(arc_length(w, 0.0, 1.0), InputError);
  const double b = 1e-5, T = 2000 * 2 * kPi;
  EXPECT_NEAR(arc_length(*make_spiral(0, b, 0, T), 0, T), b / 2 * (T * std::sqrt(1 + T * T) + std::asinh(T)),
              1e-12 * b * T * T);
}

TEST(Curves, RoseClosesAfterItsPeriod) {
  for (auto [p, q] : {std::pair{3, 1}, {2, 1}, {2, 3}, {1, 2}}) {
    auto c = make_rose(0.05, p, q);
    EXPECT_TRUE(c->closed());
    Vec2 a = c->eval(c->u_begin(), 0).p, e = c->eval(c->u_end(), 0).p;
    EXPECT_NEAR(norm(a - e), 0.0, 1e-12) << p << "/" << q;
  }
}

TEST(Spline, InterpolatesThePointsWithContinuousSecondDerivative) {
  std::vector<Vec2> pts;
  for (int i = 0; i < 12; ++i) pts.push_back({0.01 * i, 0.02 * std::sin(0.7 * i)});
  for (bool closed : {false, true}) {
    auto s = make_spline(pts, closed, "");
    auto knots = s->breakpoints();
    ASSERT_EQ(knots.size(), closed ? pts.size() - 1 : pts.size() - 2);
    EXPECT_NEAR(norm(s->eval(s->u_begin(), 0).p - pts[0]), 0, 1e-15);
    for (size_t i = 0; i < knots.size(); ++i) {
      EXPECT_NEAR(norm(s->eval(knots[i], 0).p - pts[i + 1]), 0, 1e-14);
      CurvePoint l = s->eval(std::nextafter(knots[i], 0.0), 2), r = s->eval(knots[i], 2);
      EXPECT_NEAR(norm(l.d1 - r.d1), 0, 1e-10);
      EXPECT_NEAR(norm(l.d2 - r.d2), 0, 1e-7);
    }
    if (closed) {
      CurvePoint a = s->eval(s->u_begin(), 2), e = s->eval(s->u_end(), 2);
      EXPECT_NEAR(norm(a.p - e.p), 0, 1e-14);
      EXPECT_NEAR(norm(a.d1 - e.d1), 0, 1e-10);
      EXPECT_NEAR(norm(a.d2 - e.d2), 0, 1e-7);
    } else {
      EXPECT_NEAR(norm(s->eval(s->u_begin(), 2).d2), 0, 1e-10);  // natural end conditions
      EXPECT_NEAR(norm(s->eval(s->u_end(), 2).d2), 0, 1e-10);
    }
  }
  EXPECT_THROW(make_spline({{0, 0}, {0, 0}, {1, 1}}, false, ""), InputError);
  EXPECT_THROW(make_spline({{0, 0}}, false, ""), InputError);
}

TEST(Spline, ReproducesACircleClosely) {
  std::vector<Vec2> pts;
  for (int i = 0; i < 64; ++i) pts.push_back({0.05 * std::cos(2 * kPi * i / 64), 0.05 * std::sin(2 * kPi * i / 64)});
  auto s = make_spline(pts, true, "");
  for (double u = 0; u < s->u_end(); u += s->u_end() / 1000) EXPECT_NEAR(norm(s->eval(u, 0).p), 0.05, 2e-7);
}

TEST(Path, OffsetKeepsTheToolAtItsRadius) {
  // a square, counter-clockwise, 40 mm side, offset outside (right of travel) by 3 mm: straight sides move out,
  // the corners become quarter circles of 3 mm about the square's corners
  std::vector<PathSegment> sq(4);
  Vec2 c[4] = {{0, 0}, {0.04, 0}, {0.04, 0.04}, {0, 0.04}};
  for (int i = 0; i < 4; ++i) {
    sq[i].from = c[i];
    sq[i].to = c[(i + 1) % 4];
  }
  auto off = offset_path(sq, true, -0.003);
  ASSERT_EQ(off.size(), 8u);
  auto curve = make_path(off, true);
  EXPECT_NEAR(curve->u_end(), 4 * 0.04 + 2 * kPi * 0.003, 1e-15);
  for (double u = 0; u < curve->u_end(); u += 1e-4) {
    Vec2 p = curve->eval(u, 0).p;
    // distance to the square
    double dx = std::max({0.0 - p.x, 0.0, p.x - 0.04}), dy = std::max({0.0 - p.y, 0.0, p.y - 0.04});
    EXPECT_NEAR(std::hypot(dx, dy), 0.003, 1e-12);
  }
  EXPECT_THROW(offset_path(sq, true, +0.003), InputError);  // inside: sharp concave corners
}

TEST(Path, ArcsByEndPointAndBySweep) {
  PathSegment a = make_arc_segment_to({0.1, 0}, {0, 0.1}, {0, 0}, true);
  EXPECT_NEAR(a.sweep, kPi / 2, 1e-15);
  PathSegment b = make_arc_segment_to({0.1, 0}, {0, 0.1}, {0, 0}, false);
  EXPECT_NEAR(b.sweep, -1.5 * kPi, 1e-15);
  EXPECT_THROW(make_arc_segment_to({0.1, 0}, {0, 0.2}, {0, 0}, true), InputError);
  auto p = make_path({a}, false);
  EXPECT_NEAR(curvature(p->eval(0.05, 2)), 10.0, 1e-12);
}

TEST(ToolPath, OffsetSidesAndFolds) {
  auto circle = make_circle({0, 0}, 0.05);
  auto out = make_tool_path(circle, Placement{}, ToolSpec{0.004, ToolSide::outside}, TravelSpec{});
  auto in = make_tool_path(circle, Placement{}, ToolSpec{0.004, ToolSide::inside}, TravelSpec{});
  TravelSpec rev;
  rev.reverse = true;
  auto out_rev = make_tool_path(circle, Placement{}, ToolSpec{0.004, ToolSide::outside}, rev);
  for (double u = 0.1; u < 6; u += 0.9) {
    EXPECT_NEAR(norm(out->eval(u, 0).p), 0.054, 1e-15);
    EXPECT_NEAR(norm(in->eval(u, 0).p), 0.046, 1e-15);
    EXPECT_NEAR(norm(out_rev->eval(u, 0).p), 0.054, 1e-15);
    // Q' = P'(1 - d kappa): speed of the offset circle
    EXPECT_NEAR(norm(out->eval(u, 1).d1), 0.054, 1e-15);
    // second derivative: centripetal, |Q''| = R_offset
    EXPECT_NEAR(norm(out->eval(u, 2).d2), 0.054, 1e-14);
  }
  // a tool larger than the circle cannot go inside it
  EXPECT_THROW(make_tool_path(circle, Placement{}, ToolSpec{0.06, ToolSide::inside}, TravelSpec{}), InputError);
  // limacon: inner side folds where its concave radius of curvature is smaller than the tool
  auto lim = make_limacon(0.0508, 0.0762);
  EXPECT_NO_THROW(make_tool_path(lim, Placement{}, ToolSpec{0.002, ToolSide::outside}, TravelSpec{}));
  EXPECT_THROW(make_tool_path(lim, Placement{}, ToolSpec{0.05, ToolSide::outside}, TravelSpec{}), InputError);
}

TEST(ToolPath, PlacementMovesThePole) {
  auto c = make_circle({0, 0}, 0.05);
  auto tp = make_tool_path(c, Placement{0.2, kPi / 2}, ToolSpec{}, TravelSpec{});
  // O = O1 + C e^{j beta} = (0, 0.2): the circle's point at u = pi/2 is (0, 0.05), 0.15 below the pole
  Vec2 q = tp->eval(kPi / 2, 0).p;
  EXPECT_NEAR(q.x, 0.0, 1e-15);
  EXPECT_NEAR(q.y, -0.15, 1e-15);
}

TEST(ExprCurves, PolarExpressionEqualsTheNamedLimacon) {
  auto e = make_polar_expr("b + a*cos(t)", 0, 2 * kPi, true, 0.01, {{"a", 5.08}, {"b", 7.62}});
  auto l = make_limacon(0.0508, 0.0762);
  for (double t = 0.05; t < 6.2; t += 0.3) {
    CurvePoint p = e->eval(t, 2), q = l->eval(t, 2);
    EXPECT_NEAR(norm(p.p - q.p), 0, 1e-15);
    EXPECT_NEAR(norm(p.d1 - q.d1), 0, 1e-12 * norm(q.d1));
    EXPECT_NEAR(norm(p.d2 - q.d2), 0, 1e-9 * norm(q.d2));
  }
  auto w = make_cartesian_expr("8*a^3/(x^2+4*a^2)", -0.2, 0.2, 0.01, {{"a", 21.59}});
  auto wn = make_witch(0.2159, -0.2, 0.2);
  for (double x = -0.19; x < 0.19; x += 0.05) {
    Vec2 pe = w->eval(x / 0.01, 0).p;
    EXPECT_NEAR(norm(pe - wn->eval(x, 0).p), 0, 1e-15);
  }
  auto par = make_parametric_expr("5*cos(u)", "5*sin(u)", 0, 2 * kPi, true, 0.01, {});
  EXPECT_NEAR(curvature(par->eval(1.0, 2)), 20.0, 1e-6);
  EXPECT_THROW(make_polar_expr("b + ", 0, 1, false, 0.01, {}), InputError);
  EXPECT_THROW(make_polar_expr("q*t", 0, 1, false, 0.01, {}), InputError);  // unknown name
  EXPECT_THROW(make_polar_expr("1/(t-0.5)", 0, 1, false, 0.01, {}), InputError);  // not finite
}

TEST(PointFiles, CsvAndThetaRho) {
  std::string csv = polarcam::test::temp_path("pts.csv"), thr = polarcam::test::temp_path("pts.thr");
  {
    std::ofstream f(csv);
    f << "x,y\n# comment\n1,2\n3;4\n5 6\n";
  }
  {
    std::ofstream f(thr);
    f << "# theta rho\n0 0\n1.5707963267948966 0.5\n3.141592653589793 1\n";
  }
  auto p = read_points_csv(csv, 0.001);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_DOUBLE_EQ(p[2].y, 0.006);
  // a theta-rho file is a pattern: its vertices, rho scaled, are the points x = rho cos theta, y = rho sin theta
  const ThrPattern tp = read_thr(thr);
  ASSERT_EQ(tp.vertices.size(), 3u);
  std::vector<ThetaRho> v = tp.vertices;
  for (ThetaRho& x : v) x.rho *= 0.2;
  const CurvePtr t = make_theta_rho_path(v, "pts");
  EXPECT_NEAR(t->eval(1.0, 0).p.y, 0.1, 1e-15);
  EXPECT_NEAR(t->eval(2.0, 0).p.x, -0.2, 1e-15);
  {
    std::ofstream f(csv);
    f << "x,y\n1,2\n3,abc\n";
  }
  EXPECT_THROW(read_points_csv(csv, 0.001), InputError);
  // quoted fields, as spreadsheets write them: every row a point (the first row was once taken as a header)
  {
    std::ofstream f(csv);
    f << "\"1\",\"2\"\n\"3\";\"4.5\"\n";
  }
  p = read_points_csv(csv, 0.001);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_DOUBLE_EQ(p[0].x, 0.001);
  EXPECT_DOUBLE_EQ(p[1].y, 0.0045);
  // a decimal comma inside quotes is one field that is not a number, never the two numbers 1 and 5
  {
    std::ofstream f(csv);
    f << "x,y\n\"1,5\"\n";
  }
  try {
    read_points_csv(csv, 0.001);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":2"), std::string::npos) << e.what();
  }
  std::remove(csv.c_str());
  std::remove(thr.c_str());
}

}  // namespace tu_cam_test_cam
