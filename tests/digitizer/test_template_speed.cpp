// The template digitizer's speed model: the corrected Eq. 3.3 against hand computations, the thesis's 1/8 in
// example, and the speed profile along circles, lines and an ellipse against independent integrals.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/path.hpp"
#include "cam/toolpath.hpp"
#include "digitizer/polar_track.hpp"
#include "digitizer/template_speed.hpp"

namespace tu_digitizer_test_template_speed {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kInch = 0.0254;

// x = a cos u, y = b sin u, counter-clockwise; written out here so that the test does not use the library's curves
class Ellipse final : public Curve {
 public:
  Ellipse(double a, double b) : Curve(0.0, 2.0 * kPi, true, "ellipse"), a_(a), b_(b) {}
  CurvePoint eval(double u, int order) const override {
    const double c = std::cos(u), s = std::sin(u);
    CurvePoint p;
    p.p = {a_ * c, b_ * s};
    if (order >= 1) p.d1 = {-a_ * s, b_ * c};
    if (order >= 2) p.d2 = {-a_ * c, -b_ * s};
    if (order >= 3) p.d3 = {a_ * s, -b_ * c};
    return p;
  }

 private:
  double a_, b_;
};

// Gauss-Legendre on many panels in long double, for the independent integrals.
template <class F>
long double integrate(F f, long double a, long double b, int panels) {
  static const long double x[5] = {0.0L, 0.538469310105683091036314420700208805L, 0.906179845938663992797626878299392965L};
  static const long double w[5] = {0.568888888888888888888888888888888889L, 0.478628670499366468041291514755417408L,
                                   0.236926885056189087514264040719917363L};
  long double sum = 0, h = (b - a) / panels;
  for (int k = 0; k < panels; ++k) {
    const long double m = a + (k + 0.5L) * h, r = 0.5L * h;
    sum += r * w[0] * f(m);
    for (int i = 1; i < 3; ++i) sum += r * w[i] * (f(m - r * x[i]) + f(m + r * x[i]));
  }
  return sum;
}
}  // namespace

TEST(TemplateSpeed, CorrectedEquation33AgainstHandComputation) {
  // R_r* = 1/2, rho* = 2: (3.3a) 2 (2 - 1/2) / (4 + 1) = 3/5; (3.3b) 2 (2 + 1/2) / (4 - 1) = 5/3
  EXPECT_DOUBLE_EQ(template_v_star(2.0, 0.5, CurvatureSide::roller), 0.6);
  EXPECT_DOUBLE_EQ(template_v_star(2.0, 0.5, CurvatureSide::other), 5.0 / 3.0);
  // R_r* = 1/4, rho* = 10: 2 * 9.75 / 21 and 2 * 10.25 / 19
  EXPECT_NEAR(template_v_star(10.0, 0.25, CurvatureSide::roller), 19.5 / 21.0, 1e-15);
  EXPECT_NEAR(template_v_star(10.0, 0.25, CurvatureSide::other), 20.5 / 19.0, 1e-15);
  // the roller stops where rho* = R_r* (100 % slower); a straight template runs at V_t
  EXPECT_EQ(template_v_star(0.5, 0.5, CurvatureSide::roller), 0.0);
  EXPECT_EQ(template_v_star(INFINITY, 0.5, CurvatureSide::roller), 1.0);
  EXPECT_NEAR(template_v_star(1e12, 0.5, CurvatureSide::other), 1.0, 1e-11);
  // the curvature form is the same function: c = +1/rho* on the roller's side, -1/rho* on the other
  for (double rho : {0.7, 1.5, 3.0, 40.0})
    for (double rr : {0.1, 0.5, 2.0}) {
      if (rho > rr) {
        EXPECT_NEAR(template_v_star_curvature(1.0 / rho, rr), template_v_star(rho, rr, CurvatureSide::roller), 1e-14);
      }
      EXPECT_NEAR(template_v_star_curvature(-1.0 / rho, rr), template_v_star(rho, rr, CurvatureSide::other), 1e-14);
    }
  // the slope against a central difference
  const double c = 0.3, rr = 0.5, h = 1e-6;
  EXPECT_NEAR(template_v_star_slope(c, rr),
              (template_v_star_curvature(c + h, rr) - template_v_star_curvature(c - h, rr)) / (2 * h), 1e-8);
  EXPECT_DOUBLE_EQ(template_c_max(0.5), 2.0);
  EXPECT_DOUBLE_EQ(template_c_min(0.5), -2.0 / 3.0);
}

TEST(TemplateSpeed, ThesisExampleOfAnEighthInchIsUnderTenPercentOnlyWithTheFactorTwo) {
  // rollers of 1/8 in diameter, a template 1/8 in thick, radius of curvature 5 cm (Sec. 3.5)
  const double H = kInch / 8, Rr = kInch / 16, rho = 0.05;
  const double rs = rho / H, rr = Rr / H;  // 15.748..., 0.5
  const double a = template_v_star(rs, rr, CurvatureSide::roller), b = template_v_star(rs, rr, CurvatureSide::other);
  EXPECT_NEAR(a, 30.496062992125984 / 32.496062992125984, 1e-14);
  EXPECT_NEAR(b, 32.496062992125984 / 30.496062992125984, 1e-14);
  EXPECT_LT(std::abs(a - 1.0), 0.10);
  EXPECT_LT(std::abs(b - 1.0), 0.10);
  EXPECT_GT(std::abs(a - 1.0), 0.06);  // 6.2 % and 6.6 %: not trivially small either
  EXPECT_GT(std::abs(b - 1.0), 0.06);
  // as printed (no factor 2), v / V_t is about 0.47 and 0.53: 'less than 10 %' would fail
  const double printed_a = (rs - rr) / (2 * rs + 1), printed_b = (rs + rr) / (2 * rs - 1);
  EXPECT_GT(std::abs(printed_a - 1.0), 0.5);
  EXPECT_GT(std::abs(printed_b - 1.0), 0.4);
}

TEST(TemplateSpeed, CircleRunsAtTheConstantSpeedOfItsCurvature) {
  const double R = 0.04, H = 0.004, Rr = 0.002, Vt = 0.01;
  const CurvePtr circle = make_circle({0.01, -0.02}, R);  // counter-clockwise: the left is the inside
  for (int sign : {+1, -1}) {
    const double L = 2 * kPi * R;
    auto prof = make_template_speed(*circle, 0.0, Vt, TemplateSpec{H, Rr, sign}, L);
    const double vs = template_v_star(R / H, Rr / H, sign > 0 ? CurvatureSide::roller : CurvatureSide::other);
    const double v = Vt * vs;
    for (double f : {0.0, 0.1, 0.37, 0.5, 0.99, 1.0}) {
      EXPECT_NEAR(prof->time_at(f * L), f * L / v, 1e-13 * L / v) << sign << " " << f;
      EXPECT_NEAR(prof->speed_at(f * L), v, 1e-13 * v);
      EXPECT_NEAR(prof->accel_at(f * L), 0.0, 1e-9 * v * v / R);
    }
    EXPECT_NEAR(prof->range().slowest.v_star, vs, 1e-12);
    EXPECT_NEAR(prof->range().fastest.v_star, vs, 1e-12);
    EXPECT_NEAR(prof->range().worst.radius_m, R, 1e-12);
    EXPECT_EQ(prof->range().worst.side, sign > 0 ? CurvatureSide::roller : CurvatureSide::other);
  }
}

TEST(TemplateSpeed, ToolPathOffsetRecoversTheTemplateCurvature) {
  // the tool centre runs outside a circle of radius R at distance Rr: its path has radius R + Rr, but the speed
  // follows the template's radius R
  const double R = 0.03, H = 0.003, Rr = 0.0015, Vt = 0.02;
  const ToolPathPtr path = make_tool_path(make_circle({0, 0}, R), Placement{0.1, 0.3}, ToolSpec{Rr, ToolSide::outside}, {});
  const double L = 2 * kPi * (R + Rr);
  auto prof = make_template_speed(*path, path->offset(), Vt, TemplateSpec{H, Rr, -1}, L);
  const double v = Vt * template_v_star(R / H, Rr / H, CurvatureSide::other);
  EXPECT_NEAR(prof->total_time(), L / v, 1e-13 * L / v);
  EXPECT_NEAR(prof->range().worst.radius_m, R, 1e-12);
}

TEST(TemplateSpeed, StraightLineRunsAtTheSetSpeed) {
  const double L = 0.25, Vt = 0.015;
  auto prof = make_template_speed(*make_line({0.1, 0.0}, {0.1, L}), 0.0, Vt, TemplateSpec{0.003, 0.0015, +1}, L);
  EXPECT_NEAR(prof->total_time(), L / Vt, 1e-13 * L / Vt);
  EXPECT_NEAR(prof->time_at(0.3 * L), 0.3 * L / Vt, 1e-13 * L / Vt);
  EXPECT_EQ(prof->range().worst.v_star, 1.0);
  EXPECT_TRUE(std::isinf(prof->range().worst.radius_m));
}

TEST(TemplateSpeed, EllipseTimeMatchesAnIndependentIntegral) {
  const double a = 0.06, b = 0.035, H = 0.003, Rr = 0.0015, Vt = 0.01;
  const Ellipse e(a, b);
  for (int sign : {+1, -1}) {
    // independent: t = integral |P'| / (V_t v*) du with kappa = a b / (a^2 sin^2 + b^2 cos^2)^(3/2)
    auto speed = [&](long double u) { return std::sqrt(a * a * std::sin(u) * std::sin(u) + b * b * std::cos(u) * std::cos(u)); };
    auto vstar = [&](long double u) {
      const long double q = a * a * std::sin(u) * std::sin(u) + b * b * std::cos(u) * std::cos(u);
      const long double c = sign * H * a * b / (q * std::sqrt(q));
      return 2.0L * (1.0L - (Rr / H) * c) / (2.0L + c);
    };
    const long double L = integrate([&](long double u) { return speed(u); }, 0.0L, 2 * kPi, 400);
    const long double T = integrate([&](long double u) { return speed(u) / (Vt * vstar(u)); }, 0.0L, 2 * kPi, 400);
    const long double Tq = integrate([&](long double u) { return speed(u) / (Vt * vstar(u)); }, 0.0L, kPi / 4, 100);
    const long double Lq = integrate([&](long double u) { return speed(u); }, 0.0L, kPi / 4, 100);
    auto prof = make_template_speed(e, 0.0, Vt, TemplateSpec{H, Rr, sign}, static_cast<double>(L));
    EXPECT_NEAR(prof->total_time(), static_cast<double>(T), 1e-12 * static_cast<double>(T));
    EXPECT_NEAR(prof->time_at(static_cast<double>(Lq)), static_cast<double>(Tq), 1e-12 * static_cast<double>(T));
    // slowest and fastest where the curvature is largest (a / b^2, at u = 0) and smallest (b / a^2, at u = pi/2)
    const double cmax = sign * H * a / (b * b), cmin = sign * H * b / (a * a);
    const double v1 = template_v_star_curvature(cmax, Rr / H), v2 = template_v_star_curvature(cmin, Rr / H);
    EXPECT_NEAR(prof->range().slowest.v_star, std::min(v1, v2), 1e-12);
    EXPECT_NEAR(prof->range().fastest.v_star, std::max(v1, v2), 1e-12);
    EXPECT_NEAR(prof->range().worst.radius_m, b * b / a, 1e-12);  // the tightest bend departs most from V_t
    EXPECT_NEAR(std::abs(prof->range().worst.p.x), a, 1e-9);
    // the speed at the worst point and the acceleration there (an extremum of v: zero)
    EXPECT_NEAR(prof->speed_at(prof->range().worst.s), Vt * prof->range().worst.v_star, 1e-12 * Vt);
    EXPECT_NEAR(prof->accel_at(prof->range().worst.s), 0.0, 1e-8 * Vt * Vt / b);
  }
}

TEST(TemplateSpeed, TooTightTemplatesAndCornersAreRefused) {
  const double H = 0.003, Rr = 0.0015;
  auto message = [&](const Curve& c, int sign) {
    try {
      make_template_speed(c, 0.0, 0.01, TemplateSpec{H, Rr, sign}, 1.0);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // roller inside a circle no larger than itself: it stops
  EXPECT_NE(message(*make_circle({0, 0}, 0.0014), +1).find("roller stops"), std::string::npos);
  // roller outside a circle of radius below H + Rr: the pressure roller inside does not fit
  const std::string fit = message(*make_circle({0, 0}, 0.004), -1);
  EXPECT_NE(fit.find("concave face"), std::string::npos) << fit;
  EXPECT_EQ(fit.find('\n'), std::string::npos);
  EXPECT_EQ(message(*make_circle({0, 0}, 0.0046), -1), "");  // just over H + Rr
  // a square: corners
  auto line = [](Vec2 a, Vec2 b) { return PathSegment{PathSegment::Kind::line, a, b, {}, 0.0}; };
  const CurvePtr sq = make_path({line({0, 0}, {0.05, 0}), line({0.05, 0}, {0.05, 0.05}), line({0.05, 0.05}, {0, 0.05}),
                                 line({0, 0.05}, {0, 0})}, true);
  EXPECT_NE(message(*sq, +1).find("corner"), std::string::npos);
  EXPECT_THROW(make_template_speed(*make_circle({0, 0}, 0.05), 0.0, 0.01, TemplateSpec{0.0, Rr, 1}, 1.0), InputError);
  EXPECT_THROW(make_template_speed(*make_circle({0, 0}, 0.05), 0.0, 0.01, TemplateSpec{H, -1.0, 1}, 1.0), InputError);
}

}  // namespace tu_digitizer_test_template_speed
