// The dual-input describing function of the suppressor's quantisation error (A. B. Dunckley (1978), Sec. 3.2):
// the closed forms of Eq. 3.7-3.8 (as program B.4 computes them) against the defining integrals Eq. 3.5-3.6 taken
// numerically, and the behaviour the document reads off Figs. 3.6-3.7.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cam/error.hpp"
#include "process/describing_function.hpp"

namespace polarcam::test {
namespace tu_process_test_describing_function {  // named: the test files compile together

// y(x) = x - Q(x): Q steps by D at +-(2i - 1) H / 2
double quantisation_error(double x, double D, double H) {
  const double levels = std::floor(std::abs(x) / H + 0.5);
  return x - (x < 0.0 ? -1.0 : 1.0) * D * levels;
}

struct Quadrature {
  double dc, ac, quadrature_part;
};

// Eq. 3.5-3.6 by the midpoint rule over theta
Quadrature integrals(double A, double B, double D, double H) {
  const int n = 400000;
  const double pi = std::numbers::pi, dt = 2.0 * pi / n;
  double mean = 0.0, s = 0.0, c = 0.0;
  for (int i = 0; i < n; ++i) {
    const double th = (i + 0.5) * dt;
    const double y = quantisation_error(B + A * std::sin(th), D, H);
    mean += y * dt;
    s += y * std::sin(th) * dt;
    c += y * std::cos(th) * dt;
  }
  return {mean / (2.0 * pi * B), s / (pi * A), c / (pi * A)};
}

TEST(DescribingFunction, ClosedFormsAreTheIntegrals) {
  for (double D : {1.0, 0.7}) {
    for (double B : {0.2, 0.3, 0.5, 1.1, -0.8}) {
      for (double A : {0.3, 0.7, 1.3, 2.9, 7.7}) {
        SCOPED_TRACE("D " + std::to_string(D) + " A " + std::to_string(A) + " B " + std::to_string(B));
        const auto g = process::quantiser_error_didf(A, B, D, 1.0);
        const Quadrature q = integrals(A, B, D, 1.0);
        EXPECT_NEAR(g.dc, q.dc, 2e-4 / std::abs(B));
        EXPECT_NEAR(g.ac, q.ac, 2e-4 / A);
        EXPECT_NEAR(q.quadrature_part, 0.0, 2e-4 / A);  // single-valued: no phase shift
      }
    }
  }
}

TEST(DescribingFunction, UnityUntilTheFirstJump) {
  // Sec. 3.2: "the gain is unity until the first quantization jump occurs", i.e. while |B| + A < H / 2
  for (double B : {0.0, 0.1, -0.2}) {
    const auto g = process::quantiser_error_didf(0.45 - std::abs(B), B, 1.0, 1.0);
    EXPECT_DOUBLE_EQ(g.dc, 1.0);
    EXPECT_DOUBLE_EQ(g.ac, 1.0);
  }
}

TEST(DescribingFunction, NearALevelTheGainIsLargeAndNegative) {
  // Sec. 3.2, Fig. 3.6: with B on the first switching level a small A gives "a large negative gain" (here
  // 1 - 2 / (pi A) exactly, one level met at its centre); with B away from it the gain stays 1 for small A
  EXPECT_NEAR(process::quantiser_error_didf(0.05, 0.5, 1.0, 1.0).ac, 1.0 - 2.0 / (std::numbers::pi * 0.05), 1e-12);
  EXPECT_LT(process::quantiser_error_didf(0.05, 0.5, 1.0, 1.0).ac, -10.0);
  EXPECT_DOUBLE_EQ(process::quantiser_error_didf(0.05, 0.2, 1.0, 1.0).ac, 1.0);
}

TEST(DescribingFunction, GainsFadeForLargeAmplitudes) {
  // "the overall trend is for the gains to tend to zero as the variable amplitudes tend towards infinity": with
  // D = H the error is bounded by H / 2, so both gains are O(H / amplitude)
  for (double big : {100.0, 1000.0}) {
    EXPECT_LT(std::abs(process::quantiser_error_didf(big, 0.3, 1.0, 1.0).ac), 2.0 / big);
    EXPECT_LT(std::abs(process::quantiser_error_didf(0.3, big, 1.0, 1.0).dc), 1.0 / big);
  }
  EXPECT_THROW(process::quantiser_error_didf(0.0, 0.3, 1.0, 1.0), InputError);
  EXPECT_THROW(process::quantiser_error_didf(1.0, 0.3, 1.0, -1.0), InputError);
}

}  // namespace tu_process_test_describing_function
}  // namespace polarcam::test
