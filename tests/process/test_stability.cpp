// Stability of regenerative chatter: the Nyquist limit against an independent count of the characteristic roots
// in the right half-plane (the argument principle on the imaginary axis), the simple criterion against the
// analytic minimum of a single mode's real part, the document's figures where they are reproducible.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <functional>
#include <numbers>
#include <vector>

#include "process/stability.hpp"
#include "tests/process/dunckley_cases.hpp"

namespace polarcam::test {
namespace tu_process_test_stability {  // named: the test files compile together

using C = std::complex<double>;
using process::TwoMassStructure;
using Poly = std::vector<double>;  // ascending powers

Poly mul(const Poly& a, const Poly& b) {
  Poly r(a.size() + b.size() - 1, 0.0);
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t j = 0; j < b.size(); ++j) r[i + j] += a[i] * b[j];
  return r;
}
C eval(const Poly& p, C s) {
  C v = 0.0;
  for (size_t i = p.size(); i-- > 0;) v = v * s + p[i];
  return v;
}

// The characteristic function D(s) + K_c (1 - mu e^{-sT}) N(s) of G = N / D, N and D built here from the factors of
// the equations of motion (the library expands them its own way).
struct Characteristic {
  Poly num, den;
  double mu, T;
  Characteristic(const TwoMassStructure& p, double mu_, double T_) : mu(mu_), T(T_) {
    const Poly machine{p.K_m + p.K_w, p.C_m + p.C_w, p.M_m}, work{p.K_w, p.C_w, p.M_w}, coupling{p.K_w, p.C_w};
    num = machine;
    den = mul(work, machine);
    const Poly c2 = mul(coupling, coupling);
    for (size_t i = 0; i < c2.size(); ++i) den[i] -= c2[i];
  }
  C operator()(double kc, C s) const { return eval(den, s) + kc * (1.0 - mu * std::exp(-s * T)) * eval(num, s); }
};

// Roots in the right half-plane by the argument principle: for this retarded quasi-polynomial of degree 4 the
// argument of f(j w) grows by (4 - 2 Z) pi / 2 from w = 0 to infinity. The argument is unwrapped on a grid fine
// against the delay's period, each step split until it turns less than 0.3 rad.
int unstable_roots(const Characteristic& f, double kc, double w_end) {
  const double h = std::numbers::pi / f.T / 16.0;
  double total = 0.0;
  std::function<void(double, C, double, C, int)> step = [&](double a, C fa, double b, C fb, int depth) {
    const double d = std::arg(fb / fa);
    if (std::abs(d) < 0.3 || depth > 60) {
      total += d;
      return;
    }
    const double m = 0.5 * (a + b);
    const C fm = f(kc, C(0.0, m));
    step(a, fa, m, fm, depth + 1);
    step(m, fm, b, fb, depth + 1);
  };
  double a = 0.0;
  C fa = f(kc, C(0.0, 0.0));
  while (a < w_end) {
    const double b = a + h;
    const C fb = f(kc, C(0.0, b));
    step(a, fa, b, fb, 0);
    a = b;
    fa = fb;
  }
  return static_cast<int>(std::lround(2.0 - total / std::numbers::pi));
}

TEST(ChatterStability, NyquistLimitIsWhereTheFirstRootCrossesTheAxis) {
  for (const DunckleyCase& c : kDunckleyCases) {
    SCOPED_TRACE("system " + std::to_string(c.system));
    const TwoMassStructure p = dunckley_structure(c);
    const process::NyquistLimit lim = process::nyquist_limit(process::workpiece_compliance(p), 1.0, 0.2);
    ASSERT_TRUE(lim.critical_gain);
    const double kc = *lim.critical_gain, w = lim.chatter_frequency;
    const Characteristic f(p, 1.0, 0.2);
    const double w_end = 10.0 * process::undamped_frequencies(p)[1];
    EXPECT_EQ(unstable_roots(f, 0.0, w_end), 0);
    EXPECT_EQ(unstable_roots(f, 0.999 * kc, w_end), 0) << kc;
    EXPECT_GT(unstable_roots(f, 1.001 * kc, w_end), 0) << kc;
    // at the limit j w is a root: |f| is rounding error against the size of its two terms
    EXPECT_LT(std::abs(f(kc, C(0.0, w))), 1e-9 * std::abs(eval(f.den, C(0.0, w)))) << w;
  }
}

TEST(ChatterStability, PartialOverlapAndAnotherPeriod) {
  const TwoMassStructure p{0.05, 2.0, 2e5, 0.08, 0.5, 5e4};
  for (double mu : {0.5, 0.9})
    for (double T : {0.013, 0.05}) {
      SCOPED_TRACE("mu " + std::to_string(mu) + " T " + std::to_string(T));
      const process::NyquistLimit lim = process::nyquist_limit(process::workpiece_compliance(p), mu, T);
      ASSERT_TRUE(lim.critical_gain);
      const Characteristic f(p, mu, T);
      const double w_end = 10.0 * process::undamped_frequencies(p)[1];
      EXPECT_EQ(unstable_roots(f, 0.999 * *lim.critical_gain, w_end), 0);
      EXPECT_GT(unstable_roots(f, 1.001 * *lim.critical_gain, w_end), 0);
    }
}

TEST(ChatterStability, NoOverlapNoRegenerativeLimit) {
  // mu = 0: 1 + K_c G = 0; X_w / F_c of two masses never turns past -180 degrees
  const TwoMassStructure p = dunckley_structure(kDunckleyCases[0]);
  EXPECT_FALSE(process::nyquist_limit(process::workpiece_compliance(p), 0.0, 0.2).critical_gain);
}

TEST(ChatterStability, SimpleCriterionOfOneModeIsAnalytic) {
  // G = 1 / (M s^2 + C s + K): min Re G = -1 / (4 K zeta (1 + zeta)) at w^2 = w_n^2 (1 + 2 zeta), so the limit
  // 1 / ((1 + mu) |min Re G|) = 4 K zeta (1 + zeta) / (1 + mu); a machine 1e9 times stiffer leaves one mode.
  const double M = 0.09, K = 12000.0;
  for (double zeta : {1e-4, 0.02, 0.1}) {
    const double Cw = 2.0 * zeta * std::sqrt(K * M);
    const TwoMassStructure p{0.03, 0.0, 1.2e13, M, Cw, K};
    for (double mu : {1.0, 0.5}) {
      const process::SimpleLimit s = process::simple_criterion(process::workpiece_compliance(p), mu);
      ASSERT_TRUE(s.gain);
      EXPECT_NEAR(*s.gain, 4.0 * K * zeta * (1.0 + zeta) / (1.0 + mu), 1e-6 * *s.gain) << zeta;
      EXPECT_NEAR(s.frequency, std::sqrt(K / M * (1.0 + 2.0 * zeta)), 1e-6 * s.frequency) << zeta;
    }
  }
}

TEST(ChatterStability, SimpleCriterionIsNeverAboveNyquist) {
  for (const DunckleyCase& c : kDunckleyCases) {
    const auto g = process::workpiece_compliance(dunckley_structure(c));
    for (double T : {0.2, 0.0371, 0.011}) {
      const auto n = process::nyquist_limit(g, 1.0, T);
      const auto s = process::simple_criterion(g, 1.0);
      ASSERT_TRUE(n.critical_gain && s.gain);
      EXPECT_LE(*s.gain, *n.critical_gain * (1.0 + 1e-9)) << c.system << " " << T;
    }
  }
}

// The document's figures (Sec. 2.2.4.2-2.2.4.3) where they follow from its parameters: limits within 5 %,
// frequencies within 3 %. Systems 3 and 7's limits (13 and 250) and system 1's frequency (348, the lower undamped
// mode: with T = 0.2 and G nearly real there the crossings sit at odd multiples of pi / T, 361.3) do not;
// docs/chatter.md explains them, and the test above checks polarcam's values for them.
TEST(ChatterStability, DocumentFiguresWhereReproducible) {
  for (const DunckleyCase& c : kDunckleyCases) {
    SCOPED_TRACE("system " + std::to_string(c.system));
    const auto lim = process::nyquist_limit(process::workpiece_compliance(dunckley_structure(c)), 1.0, 0.2);
    ASSERT_TRUE(lim.critical_gain);
    if (c.system != 3 && c.system != 7) {
      EXPECT_NEAR(*lim.critical_gain, c.paper_gain, 0.05 * c.paper_gain);
    }
    if (c.system != 1) {
      EXPECT_NEAR(lim.chatter_frequency, c.paper_rad_s, 0.03 * c.paper_rad_s);
    }
  }
  // and the irreproducible ones are off by more than the tolerance, as docs/chatter.md says
  const auto g3 = process::workpiece_compliance(dunckley_structure(kDunckleyCases[2]));
  EXPECT_GT(std::abs(*process::nyquist_limit(g3, 1.0, 0.2).critical_gain - 13.0), 0.05 * 13.0);
}

TEST(ChatterStability, LobesRepeatTheLimitAtEachSpeed) {
  const auto g = process::workpiece_compliance(dunckley_structure(kDunckleyCases[1]));
  const auto lobes = process::stability_lobes(g, 1.0, 4.0, 6.0, 5);
  ASSERT_EQ(lobes.size(), 5u);
  EXPECT_DOUBLE_EQ(lobes[2].spindle_speed, 5.0);
  ASSERT_TRUE(lobes[2].limit.critical_gain);
  EXPECT_DOUBLE_EQ(*lobes[2].limit.critical_gain, *process::nyquist_limit(g, 1.0, 0.2).critical_gain);
  const auto s = process::simple_criterion(g, 1.0);
  for (const auto& l : lobes) EXPECT_GE(*l.limit.critical_gain, *s.gain * (1.0 - 1e-9));
}

}  // namespace tu_process_test_stability
}  // namespace polarcam::test
