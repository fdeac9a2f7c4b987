// The tool path as SVG: sampling within the chord tolerance (checked against the circle's sagitta and the
// spiral's own equation), the document's frame, groups, markers and determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/svg_export.hpp"

namespace tu_cam_test_svg_export {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

}  // namespace

TEST(SvgExport, CircleChordsStayWithinTheTolerance) {
  const Vec2 c{0.02, -0.01};
  const double R = 0.05, tol = 1e-5;
  const auto pts = sample_curve(*make_circle(c, R), tol);
  // the chord of length L of a circle of radius R lies R - sqrt(R^2 - L^2 / 4) inside it at its middle
  double worst = 0;
  for (size_t k = 0; k < pts.size(); ++k) {
    EXPECT_NEAR(norm(pts[k] - c), R, 1e-15);
    if (k > 0) {
      const double L = norm(pts[k] - pts[k - 1]);
      worst = std::max(worst, R - std::sqrt(R * R - L * L / 4));
    }
  }
  EXPECT_LE(worst, tol);
  EXPECT_GT(worst, tol / 8);  // and not needlessly fine
  EXPECT_LT(norm(pts.front() - pts.back()), 1e-15);
}

TEST(SvgExport, ThetaRhoSegmentsAreSampledAsTheirSpirals) {
  // one segment from (0, 10 mm) to (6 rad, 40 mm): every sample on rho = 0.01 + 0.005 theta
  const auto pts = sample_theta_rho({{0.0, 0.01}, {6.0, 0.04}}, 1e-5);
  EXPECT_GT(pts.size(), 50u);
  double theta = 0;
  for (size_t k = 0; k < pts.size(); ++k) {
    const double a = std::atan2(pts[k].y, pts[k].x);
    theta = k == 0 ? a : theta + std::remainder(a - theta, 2 * std::numbers::pi);
    EXPECT_NEAR(norm(pts[k]), 0.01 + 0.005 * theta, 1e-14) << k;
  }
  EXPECT_NEAR(theta, 6.0, 1e-12);
}

TEST(SvgExport, ALongPolylineIsSampledWithinTheToleranceWithoutSixteenChordsASegment) {
  // 5000 spiral segments of 0.05 rad each, rho from 10 to 100 mm: every chord within the tolerance of its spiral
  // (checked at 64 points of the spiral between the chord's ends, found by their angles), and no more chords than
  // a short segment needs: a segment of 0.05 rad at 100 mm has a sagitta of 100 mm (1 - cos 0.025) = 0.031 mm,
  // so at 0.025 mm a segment takes one or two chords, not sixteen.
  std::vector<ThetaRho> v;
  const int n = 5000;
  for (int i = 0; i <= n; ++i) v.push_back({0.05 * i, 0.01 + 0.09 * i / n});
  const double tol = 2.5e-5;
  const auto pts = sample_theta_rho(v, tol);
  EXPECT_LE(pts.size(), static_cast<size_t>(3 * n));
  EXPECT_GE(pts.size(), static_cast<size_t>(n));
  const auto rho_at = [&](double theta) {  // the spiral through the vertices, linear in theta per segment
    const double i = std::clamp(theta / 0.05, 0.0, static_cast<double>(n));
    return 0.01 + 0.09 * i / n;
  };
  double theta = 0, worst = 0;
  for (size_t k = 1; k < pts.size(); ++k) {
    const double a0 = theta;
    theta += std::remainder(std::atan2(pts[k].y, pts[k].x) - std::atan2(pts[k - 1].y, pts[k - 1].x), 2 * std::numbers::pi);
    for (int j = 1; j < 64; ++j) {
      const double t = a0 + (theta - a0) * j / 64.0, r = rho_at(t);
      const Vec2 p{r * std::cos(t), r * std::sin(t)}, a = pts[k - 1], b = pts[k], d = b - a;
      const double u = std::clamp(dot(p - a, d) / dot(d, d), 0.0, 1.0);
      worst = std::max(worst, norm(p - (a + u * d)));
    }
  }
  EXPECT_LE(worst, tol);
  EXPECT_NEAR(theta, 0.05 * n, 1e-9);
}

TEST(SvgExport, DocumentInMillimetresWithYUp) {
  SvgOptions o;
  o.work_radius = 0.15;
  o.work_radius_min = 0.02;
  o.title = "limacon <a & b>";
  const std::vector<SvgPolyline> lines{{{{0.01, 0.02}, {0.03, 0.02}, {0.03, 0.05}}, true},
                                       {{{0.03, 0.05}, {-0.04, -0.06}}, false},
                                       {{{-0.04, -0.06}, {-0.07, -0.06}}, true}};
  const std::string s = svg_document(lines, o);
  // 150 mm work radius + 5 mm margin on each side; the viewBox spans -y1 .. -y0 of the flipped content
  EXPECT_NE(s.find("width=\"310.0000mm\" height=\"310.0000mm\" viewBox=\"-155.0000 -155.0000 310.0000 310.0000\""),
            std::string::npos);
  EXPECT_NE(s.find("transform=\"scale(1,-1)\""), std::string::npos);
  EXPECT_NE(s.find("<circle cx=\"0\" cy=\"0\" r=\"150.0000\"/>"), std::string::npos);
  EXPECT_NE(s.find("<circle cx=\"0\" cy=\"0\" r=\"20.0000\"/>"), std::string::npos);
  EXPECT_NE(s.find("<title>limacon &lt;a &amp; b&gt;</title>"), std::string::npos);
  // the drawn parts in the path group, the connecting move in its own
  const size_t path = s.find("<g id=\"path\""), conn = s.find("<g id=\"connecting\""), mark = s.find("<g id=\"markers\"");
  ASSERT_NE(path, std::string::npos);
  ASSERT_NE(conn, std::string::npos);
  ASSERT_NE(mark, std::string::npos);
  EXPECT_EQ(count(s.substr(path, mark - path), "<polyline"), 2u);
  EXPECT_EQ(count(s.substr(conn, path - conn), "<polyline"), 1u);
  EXPECT_NE(s.substr(path, mark - path).find("10.0000,20.0000 30.0000,20.0000 30.0000,50.0000"), std::string::npos);
  EXPECT_NE(s.substr(conn, path - conn).find("30.0000,50.0000 -40.0000,-60.0000"), std::string::npos);
  // the start marker at the first drawn point, the end marker centred on the last
  EXPECT_NE(s.find("id=\"start\" fill=\"#2e7d32\" cx=\"10.0000\" cy=\"20.0000\""), std::string::npos);
  // the stroke is 1.5e-3 of the drawing's size (310 mm): 0.465 mm; the end square is 6 strokes wide
  EXPECT_NE(s.find("id=\"end\" fill=\"#c62828\" x=\"-71.3950\" y=\"-61.3950\" width=\"2.7900\""), std::string::npos);
  EXPECT_EQ(s, svg_document(lines, o));
}

TEST(SvgExport, ExtentFromThePointsWithoutAWorkArea) {
  SvgOptions o;
  o.margin = 0.001;
  const std::string s = svg_document({{{{0.01, 0.02}, {0.03, 0.04}}, true}}, o);
  // the pole is always inside: x from -1 to 31 mm, y from -1 to 41 mm (viewBox y from -41)
  EXPECT_NE(s.find("width=\"32.0000mm\" height=\"42.0000mm\" viewBox=\"-1.0000 -41.0000 32.0000 42.0000\""),
            std::string::npos)
      << s;
}

TEST(SvgExport, RefusesABadTolerance) {
  EXPECT_THROW(sample_curve(*make_circle({0, 0}, 0.01), 0.0), InputError);
}

}  // namespace tu_cam_test_svg_export
