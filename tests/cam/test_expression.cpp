// Expressions typed by the user: exact derivatives (against derivatives differentiated by hand), the same syntax
// as muparser (values against muparser's own), and the functions refused in one line naming the key.
#include <gtest/gtest.h>
#include <muParser.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "cam/expr_curves.hpp"
#include "cam/expression.hpp"

namespace tu_cam_test_expression {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

constexpr double kPi = std::numbers::pi;

// got within `rel` of want, relative to |want| (and to `floor` where want is near zero)
void expect_rel(double got, double want, double rel, double floor, const std::string& what) {
  EXPECT_NEAR(got, want, rel * std::max(std::abs(want), floor)) << what;
}

struct Hand {
  const char* text;
  double k, c;                                  // the argument is k x + c
  std::function<void(double, double[4])> phi;   // phi and its derivatives at the argument, by hand
  std::vector<double> xs;
};

// Each function of the grammar at an affine argument: d^n/dx^n phi(k x + c) = k^n phi^(n)(k x + c).
TEST(Expression, DerivativesOfEachFunctionMatchHandDifferentiation) {
  const double L2 = std::log(2.0), L10 = std::log(10.0);
  const std::vector<double> xs{-0.9, -0.35, 0.25, 0.8};
  const std::vector<Hand> cases{
      {"sin(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) { p[0] = std::sin(u), p[1] = std::cos(u), p[2] = -std::sin(u), p[3] = -std::cos(u); }, xs},
      {"cos(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) { p[0] = std::cos(u), p[1] = -std::sin(u), p[2] = -std::cos(u), p[3] = std::sin(u); }, xs},
      {"tan(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) {
         const double s = std::sin(u), c = std::cos(u);
         p[0] = s / c, p[1] = 1 / (c * c), p[2] = 2 * s / (c * c * c), p[3] = (2 + 4 * s * s) / std::pow(c, 4); }, xs},
      {"asin(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) {
         const double q = 1 - u * u;
         p[0] = std::asin(u), p[1] = std::pow(q, -0.5), p[2] = u * std::pow(q, -1.5), p[3] = (1 + 2 * u * u) * std::pow(q, -2.5); }, xs},
      {"acos(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) {
         const double q = 1 - u * u;
         p[0] = std::acos(u), p[1] = -std::pow(q, -0.5), p[2] = -u * std::pow(q, -1.5), p[3] = -(1 + 2 * u * u) * std::pow(q, -2.5); }, xs},
      {"atan(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) {
         const double q = 1 + u * u;
         p[0] = std::atan(u), p[1] = 1 / q, p[2] = -2 * u / (q * q), p[3] = (6 * u * u - 2) / (q * q * q); }, xs},
      {"sinh(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) { p[0] = p[2] = std::sinh(u), p[1] = p[3] = std::cosh(u); }, xs},
      {"cosh(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) { p[0] = p[2] = std::cosh(u), p[1] = p[3] = std::sinh(u); }, xs},
      {"tanh(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) {
         const double s = std::sinh(u), c = std::cosh(u);
         p[0] = s / c, p[1] = 1 / (c * c), p[2] = -2 * s / (c * c * c), p[3] = (4 * s * s - 2) / std::pow(c, 4); }, xs},
      {"asinh(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) {
         const double q = 1 + u * u;
         p[0] = std::asinh(u), p[1] = std::pow(q, -0.5), p[2] = -u * std::pow(q, -1.5), p[3] = (2 * u * u - 1) * std::pow(q, -2.5); }, xs},
      {"acosh(0.7*x+2)", 0.7, 2.0, [](double u, double p[4]) {
         const double q = u * u - 1;
         p[0] = std::acosh(u), p[1] = std::pow(q, -0.5), p[2] = -u * std::pow(q, -1.5), p[3] = (2 * u * u + 1) * std::pow(q, -2.5); }, xs},
      {"atanh(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) {
         const double q = 1 - u * u;
         p[0] = std::atanh(u), p[1] = 1 / q, p[2] = 2 * u / (q * q), p[3] = (2 + 6 * u * u) / (q * q * q); }, xs},
      {"exp(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) { p[0] = p[1] = p[2] = p[3] = std::exp(u); }, xs},
      {"log(0.7*x+1)", 0.7, 1.0, [](double u, double p[4]) { p[0] = std::log(u), p[1] = 1 / u, p[2] = -1 / (u * u), p[3] = 2 / (u * u * u); }, xs},
      {"ln(0.7*x+1)", 0.7, 1.0, [](double u, double p[4]) { p[0] = std::log(u), p[1] = 1 / u, p[2] = -1 / (u * u), p[3] = 2 / (u * u * u); }, xs},
      {"log2(0.7*x+1)", 0.7, 1.0, [L2](double u, double p[4]) { p[0] = std::log2(u), p[1] = 1 / (u * L2), p[2] = -1 / (u * u * L2), p[3] = 2 / (u * u * u * L2); }, xs},
      {"log10(0.7*x+1)", 0.7, 1.0, [L10](double u, double p[4]) { p[0] = std::log10(u), p[1] = 1 / (u * L10), p[2] = -1 / (u * u * L10), p[3] = 2 / (u * u * u * L10); }, xs},
      {"sqrt(0.7*x+1)", 0.7, 1.0, [](double u, double p[4]) {
         p[0] = std::sqrt(u), p[1] = 0.5 / std::sqrt(u), p[2] = -0.25 * std::pow(u, -1.5), p[3] = 0.375 * std::pow(u, -2.5); }, xs},
      {"abs(0.7*x+0.2)", 0.7, 0.2, [](double u, double p[4]) { p[0] = std::abs(u), p[1] = u < 0 ? -1 : 1, p[2] = p[3] = 0; }, xs},
      {"(0.7*x+0.2)^3", 0.7, 0.2, [](double u, double p[4]) { p[0] = u * u * u, p[1] = 3 * u * u, p[2] = 6 * u, p[3] = 6; }, xs},
      {"(0.7*x+1)^-1.5", 0.7, 1.0, [](double u, double p[4]) {
         p[0] = std::pow(u, -1.5), p[1] = -1.5 * std::pow(u, -2.5), p[2] = 3.75 * std::pow(u, -3.5), p[3] = -13.125 * std::pow(u, -4.5); }, xs},
  };
  for (const Hand& h : cases) {
    Expression e(h.text, {"x"}, {}, "r");
    for (double x : h.xs) {
      double phi[4], got[4];
      h.phi(h.k * x + h.c, phi);
      e.derivatives(x, 3, got);
      double kn = 1.0;
      for (int n = 0; n <= 3; ++n, kn *= h.k)
        expect_rel(got[n], kn * phi[n], 1e-14, 1e-3, std::string(h.text) + " order " + std::to_string(n) + " at x = " + std::to_string(x));
    }
  }
}

// Products, quotients, powers and compositions: derivatives of whole formulas by hand.
TEST(Expression, DerivativesOfCompositeFormulasMatchHandDifferentiation) {
  const double a = 5.08, b = 7.62, L = std::log(2.0);
  const ExprConstants k{{"a", a}, {"b", b}};
  struct Formula {
    const char* text;
    std::function<void(double, double[4])> d;
    std::vector<double> xs;
  };
  const std::vector<Formula> cases{
      // the limacon's coordinates: (b + a cos u) cos u = b cos u + a/2 (1 + cos 2u), (b + a cos u) sin u
      {"(b + a*cos(u))*cos(u)", [&](double u, double d[4]) {
         d[0] = b * std::cos(u) + 0.5 * a * (1 + std::cos(2 * u)), d[1] = -b * std::sin(u) - a * std::sin(2 * u);
         d[2] = -b * std::cos(u) - 2 * a * std::cos(2 * u), d[3] = b * std::sin(u) + 4 * a * std::sin(2 * u); },
       {0.1, 0.319068, 1.94356, 4.0, 255.963}},
      {"(b + a*cos(u))*sin(u)", [&](double u, double d[4]) {
         d[0] = b * std::sin(u) + 0.5 * a * std::sin(2 * u), d[1] = b * std::cos(u) + a * std::cos(2 * u);
         d[2] = -b * std::sin(u) - 2 * a * std::sin(2 * u), d[3] = -b * std::cos(u) - 4 * a * std::cos(2 * u); },
       {0.3, 1.17875, 2.5, 5.5, 127.935}},
      {"u/(1+u^2)", [](double x, double d[4]) {
         const double q = 1 + x * x;
         d[0] = x / q, d[1] = (1 - x * x) / (q * q), d[2] = 2 * x * (x * x - 3) / (q * q * q);
         d[3] = -6 * (x * x * x * x - 6 * x * x + 1) / (q * q * q * q); },
       {-2.0, -0.5, 0.3, 1.7}},
      {"u^u", [](double x, double d[4]) {
         const double f = std::pow(x, x), l = std::log(x) + 1;
         d[0] = f, d[1] = f * l, d[2] = f * (l * l + 1 / x), d[3] = f * (l * l * l + 3 * l / x - 1 / (x * x)); },
       {0.2, 0.9, 1.5, 3.0}},
      {"2^-u^2", [L](double x, double d[4]) {
         const double f = std::exp(-L * x * x);
         d[0] = f, d[1] = -2 * L * x * f, d[2] = (4 * L * L * x * x - 2 * L) * f, d[3] = (12 * L * L * x - 8 * L * L * L * x * x * x) * f; },
       {-1.3, -0.4, 0.6, 2.1}},
      {"sqrt(1+u^2)", [](double x, double d[4]) {
         const double s = std::sqrt(1 + x * x);
         d[0] = s, d[1] = x / s, d[2] = 1 / (s * s * s), d[3] = -3 * x / std::pow(s, 5); },
       {-3.0, -0.2, 0.7, 4.0}},
  };
  for (const Formula& f : cases) {
    Expression e(f.text, {"u", "t"}, k, "x");
    for (double u : f.xs) {
      double want[4], got[4];
      f.d(u, want);
      e.derivatives(u, 3, got);
      // the scale of a derivative: the formula's largest term (the limacon's b + 4a), so that near-zero values
      // are held to the rounding of the numbers they come from
      for (int n = 0; n <= 3; ++n)
        expect_rel(got[n], want[n], 1e-14, std::string(f.text).find('a') != std::string::npos ? b + 4 * a : 1e-3,
                   std::string(f.text) + " order " + std::to_string(n) + " at u = " + std::to_string(u));
    }
    // lower orders give the same numbers and zeros above
    double o1[4];
    e.derivatives(f.xs[0], 1, o1);
    double o3[4];
    e.derivatives(f.xs[0], 3, o3);
    EXPECT_EQ(o1[0], o3[0]);
    EXPECT_EQ(o1[1], o3[1]);
    EXPECT_EQ(o1[2], 0.0);
    EXPECT_EQ(o1[3], 0.0);
  }
}

// The parser reads what muparser reads, the same way: precedence (-x^2 = -(x^2), ^ right-associative), numbers,
// constants, several-argument functions. The values are muparser's own, to a few units in the last place.
TEST(Expression, ValuesAreMuparsersOnTheSameText) {
  const ExprConstants k{{"a", 1.25}, {"r0", 3.0}};
  const char* texts[] = {
      "-x^2", "2^-x^2", "2^3^x", "x^0.5^2", "-2^-x", "3 - -x", "2*-x", "+x", "1e-3*x + .5 - 5.", "1E2/x",
      "x/2/3", "x-1-2", "2^x^2", "-x*3", "sin(x)^2+cos(x)^2", "exp(-(x-0.3)^2/0.1)", "tan(x)*atan(x)",
      "sqrt(1+x^2)", "sinh(x)-cosh(x)+tanh(x)", "asinh(x)+atanh(x/2)+acosh(x+2)", "asin(x/2)+acos(x/2)",
      "log(x)+ln(x)+log2(x)+log10(x)", "min(x, 1-x, 0.3)", "max(x,0.2)", "sum(x,2,3)", "avg(x,1)",
      "abs(x-0.5)", "_pi*x + _e", "pi*a*x^2 + r0", "( x + a ) * ( x - a )", "x^-1.5", "(-x)^3", "a^x"};
  for (const char* t : texts) {
    Expression e(t, {"x"}, k, "r");
    mu::Parser p;
    double var = 0;
    p.DefineConst("pi", kPi);
    for (const auto& [n, v] : k) p.DefineConst(n, v);
    p.DefineVar("x", &var);
    p.SetExpr(t);
    for (double x : {0.15, 0.5, 0.9, 1.7}) {
      var = x;
      const double want = p.Eval();
      expect_rel(e(x), want, 4e-16, 1e-300, std::string(t) + " at x = " + std::to_string(x));
    }
  }
}

// The size of the numbers a value comes from beyond the value: none where nothing cancels, the cancelled terms
// where something does (carried through products and functions by hand here).
TEST(Expression, ExcessMeasuresCancellation) {
  EXPECT_EQ(Expression("2*x + 3", {"x"}, {}, "r").excess(1.0), 0.0);
  EXPECT_EQ(Expression("(7.62 + 5.08*cos(x))*cos(x)", {"x"}, {}, "r").excess(0.0), 0.0);
  // 1e6 + 20 cos x - 1e6: both 1e6 terms, and 20 |cos x| beyond |20 cos x| itself (none)
  EXPECT_DOUBLE_EQ(Expression("1e6 + 20*cos(x) - 1e6", {"x"}, {}, "r").excess(0.5), 2e6);
  // (b + a cos x) at cos x = -1/2: T = b + a/2 against |b - a/2|, an excess of a, scaled by the factor 3
  EXPECT_NEAR(Expression("3*(7.62 + 5.08*cos(x))", {"x"}, {}, "r").excess(2 * kPi / 3), 3 * 5.08, 1e-12);
  // sin of an argument with excess e: |cos| e on top of |sin|
  EXPECT_DOUBLE_EQ(Expression("sin(1000 + x - 1000)", {"x"}, {}, "r").excess(0.25), std::cos(0.25) * 2000);
}

// Where abs, min and max turn a corner the derivatives are those just after the point (increasing variable).
TEST(Expression, CornersTakeTheDerivativeOnTheRight) {
  double d[4];
  Expression("abs(x-0.5)", {"x"}, {}, "r").derivatives(0.5, 3, d);
  EXPECT_EQ(d[0], 0.0);
  EXPECT_EQ(d[1], 1.0);
  Expression("abs(0.5-x)", {"x"}, {}, "r").derivatives(0.5, 3, d);
  EXPECT_EQ(d[1], 1.0);
  Expression("min(x, 1-x)", {"x"}, {}, "r").derivatives(0.5, 3, d);
  EXPECT_EQ(d[0], 0.5);
  EXPECT_EQ(d[1], -1.0);
  Expression("max(x, 1-x)", {"x"}, {}, "r").derivatives(0.5, 3, d);
  EXPECT_EQ(d[1], 1.0);
  Expression("max(x^2, 2*x-1)", {"x"}, {}, "r").derivatives(1.0, 3, d);  // tangent there: the curvature decides
  EXPECT_EQ(d[2], 2.0);
}

// Refused in one line, placed at the key, naming the function or operator and why.
TEST(Expression, StepsAndChoicesAreRefusedNamingTheKeyAndTheFunction) {
  struct Bad {
    const char* text;
    const char* mention;
  };
  for (const Bad& b : {Bad{"20*sign(cos(u))", "sign()"}, Bad{"rint(u)", "rint()"}, Bad{"u < 1", "'<'"},
                       Bad{"u > 1 ? 1 : 2", "'>'"}, Bad{"u ? 1 : 2", "'?:'"}, Bad{"(u > 1) ? 1 : 2", "'>'"}, Bad{"u && 1", "logical operator '&&'"}, Bad{"u <= 1", "comparison operator '<='"},
                       Bad{"u, 1", "','"}, Bad{"q*u", "q"}, Bad{"cos(u", "parenthesis"}}) {
    try {
      Expression e(b.text, {"u"}, {}, "x");
      ADD_FAILURE() << b.text << " was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.place(), "x") << b.text;
      EXPECT_NE(e.message().find(b.mention), std::string::npos) << e.message();
      EXPECT_NE(e.message().find(b.text), std::string::npos) << e.message();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
}

// Deep nesting is refused in one line (the parser's recursion is bounded), not a crash.
TEST(Expression, DeepNestingIsRefused) {
  const std::string deep = std::string(300, '(') + "x" + std::string(300, ')');
  try {
    Expression e(deep, {"x"}, {}, "r");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "r");
    EXPECT_NE(e.message().find("nested too deeply"), std::string::npos) << e.message();
  }
  EXPECT_EQ(Expression(std::string(100, '(') + "x" + std::string(100, ')'), {"x"}, {}, "r")(0.5), 0.5);
}

// Long chains: a product of 1000 factors (x + 1) is (x + 1)^1000 with its derivatives, and a chain of 1200 constant
// products folds to the constant muparser computes; a text beyond 10 000 characters is refused naming its key.
TEST(Expression, LongChainsAreExactAndOverlongTextIsRefused) {
  std::string chain = "(x+1)";
  for (int i = 1; i < 1000; ++i) chain += "*(x+1)";
  const Expression e(chain, {"x"}, {}, "r");
  double d[4];
  e.derivatives(0.001, 3, d);
  const double b = 1.001;
  expect_rel(d[0], std::pow(b, 1000), 1e-12, 0.0, "value");
  expect_rel(d[1], 1000 * std::pow(b, 999), 1e-12, 0.0, "first derivative");
  expect_rel(d[2], 1000.0 * 999 * std::pow(b, 998), 1e-12, 0.0, "second derivative");
  expect_rel(d[3], 1000.0 * 999 * 998 * std::pow(b, 997), 1e-12, 0.0, "third derivative");
  std::string konst = "1.0001";
  for (int i = 1; i < 1200; ++i) konst += "*1.0001";
  mu::Parser p;
  p.SetExpr(konst);
  expect_rel(Expression(konst + "*x", {"x"}, {}, "r")(1.0), p.Eval(), 4e-16, 0.0, "constant chain");
  std::string overlong = "x";
  while (overlong.size() <= kMaxExpressionLength) overlong += "+x";
  try {
    Expression bad(overlong, {"x"}, {}, "r");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& ex) {
    EXPECT_EQ(ex.place(), "r");
    EXPECT_NE(ex.message().find("at most 10000 are read"), std::string::npos) << ex.message();
  }
}

// The curves built on expressions: the parametric limacon's position and derivatives are the hand-differentiated
// ones (and the named limacon's); the polar one the same curve.
TEST(ExpressionCurves, LimaconDerivativesAreExact) {
  const double a = 5.08, b = 7.62, unit = 0.01;
  const ExprConstants k{{"a", a}, {"b", b}};
  auto par = make_parametric_expr("(b + a*cos(u))*cos(u)", "(b + a*cos(u))*sin(u)", 0, 2 * kPi, true, unit, k);
  auto pol = make_polar_expr("b + a*cos(t)", 0, 2 * kPi, true, unit, k);
  auto named = make_limacon(a * unit, b * unit);
  const double scale = (b + 4 * a) * unit;
  for (double u : {0.0, 0.319068, 0.985399, 1.94356, 3.3, 5.9}) {
    const CurvePoint p = par->eval(u, 3), q = pol->eval(u, 3), n = named->eval(u, 3);
    const double c = std::cos(u), s = std::sin(u), c2 = std::cos(2 * u), s2 = std::sin(2 * u);
    const Vec2 want[4] = {Vec2{b * c + 0.5 * a * (1 + c2), b * s + 0.5 * a * s2} * unit,
                          Vec2{-b * s - a * s2, b * c + a * c2} * unit,
                          Vec2{-b * c - 2 * a * c2, -b * s - 2 * a * s2} * unit,
                          Vec2{b * s + 4 * a * s2, -b * c - 4 * a * c2} * unit};
    const Vec2 gp[4] = {p.p, p.d1, p.d2, p.d3}, gq[4] = {q.p, q.d1, q.d2, q.d3}, gn[4] = {n.p, n.d1, n.d2, n.d3};
    for (int o = 0; o < 4; ++o) {
      EXPECT_LE(norm(gp[o] - want[o]), 1e-14 * scale) << "parametric order " << o << " at u = " << u;
      EXPECT_LE(norm(gq[o] - want[o]), 1e-14 * scale) << "polar order " << o << " at u = " << u;
      EXPECT_LE(norm(gn[o] - want[o]), 1e-14 * scale) << "named order " << o << " at u = " << u;
    }
  }
}

TEST(ExpressionCurves, ErrorsArePlacedAtTheirKeys) {
  try {
    make_parametric_expr("cos(u)", "sign(sin(u))", 0, 1, false, 0.01, {});
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "y");
  }
  try {
    make_polar_expr("1/(t-0.5)", 0, 1, false, 0.01, {});
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "r");
    EXPECT_NE(e.message().find("not finite at t = 0.5"), std::string::npos) << e.message();
  }
}

}  // namespace

}  // namespace tu_cam_test_expression
