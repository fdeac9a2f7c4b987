#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "digitizer/chebyshev.hpp"
#include "digitizer/polar_track.hpp"

namespace tu_digitizer_test_chebyshev {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {
Cheb fit(double (*f)(double)) {
  const auto& t = cheb_points();
  std::array<double, kChebMaxDegree + 1> v;
  for (int j = 0; j <= kChebMaxDegree; ++j) v[j] = f(t[j]);
  return cheb_fit(v.data(), kChebMaxDegree);
}
}  // namespace

TEST(Chebyshev, InterpolatesSmoothFunctionsToRounding) {
  Cheb c = fit([](double x) { return std::exp(0.5 * x); });
  for (double x = -1; x <= 1; x += 0.01) EXPECT_NEAR(c(x), std::exp(0.5 * x), 1e-15);
  EXPECT_LT(cheb_tail(c), 1e-15);
}

TEST(Chebyshev, DerivativeAndIntegralOfAPolynomialAreExact) {
  // p(x) = 3x^3 - x + 2: p' = 9x^2 - 1, integral from -1 = 3/4 x^4 - x^2/2 + 2x - (3/4 - 1/2 - 2)
  Cheb c = fit([](double x) { return 3 * x * x * x - x + 2; });
  cheb_chop(c, 1e-14);
  EXPECT_EQ(c.deg, 3);
  Cheb d = c.derivative(), I = c.integral();
  for (double x = -1; x <= 1; x += 0.125) {
    EXPECT_NEAR(d(x), 9 * x * x - 1, 1e-13);
    EXPECT_NEAR(I(x), 0.75 * x * x * x * x - 0.5 * x * x + 2 * x - (0.75 - 0.5 - 2), 1e-13);
    double f, df;
    c.eval2(x, f, df);
    EXPECT_NEAR(df, 9 * x * x - 1, 1e-13);
  }
}

TEST(Chebyshev, DegreeEightFitUsesEveryOtherPoint) {
  const auto& t = cheb_points();
  std::array<double, 9> v;
  for (int j = 0; j <= 8; ++j) v[j] = std::cos(t[2 * j]);
  Cheb c = cheb_fit(v.data(), 8);
  for (double x = -1; x <= 1; x += 0.1) EXPECT_NEAR(c(x), std::cos(x), 1e-9);
}

TEST(Chebyshev, SolveAndSignChanges) {
  Cheb c = fit([](double x) { return std::sin(2 * x); });
  double r = cheb_solve(c, 0.5, 0.0, 0.5, c(0.0) - 0.5, c(0.5) - 0.5);
  EXPECT_NEAR(r, std::acos(-1.0) / 12, 1e-14);
  // sin(2x) turns at +-pi/4 inside [-1, 1]
  Cheb d = c.derivative();
  std::vector<double> roots;
  cheb_sign_changes(d, roots);
  ASSERT_EQ(roots.size(), 2u);
  EXPECT_NEAR(roots[0], -std::acos(-1.0) / 4, 1e-13);
  EXPECT_NEAR(roots[1], std::acos(-1.0) / 4, 1e-13);
  // a dip that just crosses zero between samples: x^2 - 1e-6 has two close roots
  Cheb q = fit([](double x) { return (x - 0.3) * (x - 0.3) - 1e-8; });
  roots.clear();
  cheb_sign_changes(q, roots);
  ASSERT_EQ(roots.size(), 2u);
  EXPECT_NEAR(roots[0], 0.3 - 1e-4, 1e-12);
  EXPECT_NEAR(roots[1], 0.3 + 1e-4, 1e-12);
}

}  // namespace tu_digitizer_test_chebyshev

namespace tu_digitizer_test_chebyshev {

// The tail of a fit formed alone is the tail of the whole fit, to the bit (the track builder refuses a fit on it
// before forming the other coefficients, and must refuse exactly the fits it refused before).
TEST(Chebyshev, TailAloneIsTheWholeFitsTail) {
  uint64_t seed = 12345;
  auto uniform = [&] {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(seed >> 11) * 0x1.0p-53;
  };
  for (int n : {8, 16}) {
    for (int trial = 0; trial < 200; ++trial) {
      std::array<double, kChebMaxDegree + 1> v{};
      const double scale = std::pow(10.0, -12.0 + 14.0 * uniform());
      for (int j = 0; j <= n; ++j) v[j] = scale * (2.0 * uniform() - 1.0);
      const double whole = cheb_tail(cheb_fit(v.data(), n));
      EXPECT_EQ(std::bit_cast<uint64_t>(cheb_fit_tail(v.data(), n)), std::bit_cast<uint64_t>(whole)) << n << " " << trial;
    }
  }
}

// A series whose constant term outweighs the others keeps its sign: no sign change is reported, and a dense
// evaluation agrees; one whose constant term is just short of that, with a turning point that dips through zero,
// still has its two sign changes found.
TEST(Chebyshev, DominantConstantTermHasNoSignChange) {
  Cheb c;
  c.deg = 6;
  c.c = {};
  c.c[0] = 1.0;
  c.c[2] = -0.4, c.c[4] = 0.3, c.c[6] = -0.29;  // sum of the rest 0.99 < 1
  std::vector<double> roots;
  cheb_sign_changes(c, roots);
  EXPECT_TRUE(roots.empty());
  for (double x = -1; x <= 1; x += 1e-4) EXPECT_GT(c(x), 0.0) << x;
  // -0.3 T_2 (x) dips to 1 - 0.3 - ... : with c_2 = -1.2 the series 1 - 1.2 T_2 is negative about x = 0
  Cheb d;
  d.deg = 2;
  d.c = {};
  d.c[0] = 1.0;
  d.c[2] = -1.2;  // 1 - 1.2 (2x^2 - 1) = 2.2 - 2.4 x^2: roots at +-sqrt(2.2 / 2.4)
  cheb_sign_changes(d, roots);
  ASSERT_EQ(roots.size(), 2u);
  EXPECT_NEAR(roots[0], -std::sqrt(2.2 / 2.4), 1e-14);
  EXPECT_NEAR(roots[1], std::sqrt(2.2 / 2.4), 1e-14);
}

}  // namespace tu_digitizer_test_chebyshev
