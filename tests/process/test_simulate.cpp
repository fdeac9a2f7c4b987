// The time-domain simulation of the delay-differential system: a gain a little under the Nyquist limit decays, a
// little over grows at the Nyquist chatter frequency (A. B. Dunckley (1978), Sec. 2.3 found 8 % and 3 %); without
// regeneration the cut settles where the springs and the cutting stiffness balance.
#include <gtest/gtest.h>

#include <cmath>

#include "cam/error.hpp"
#include "process/simulate.hpp"
#include "process/stability.hpp"
#include "tests/process/dunckley_cases.hpp"

namespace polarcam::test {
namespace tu_process_test_simulate {  // named: the test files compile together

TEST(ChatterSimulation, UnderTheLimitDecaysOverItGrows) {
  for (int i : {1, 3}) {  // systems 2 and 4
    const DunckleyCase& c = kDunckleyCases[i];
    SCOPED_TRACE("system " + std::to_string(c.system));
    const process::TwoMassStructure p = dunckley_structure(c);
    process::Cut cut;
    cut.overlap = 1.0;
    cut.revolution_period = 0.2;
    const auto lim = process::nyquist_limit(process::workpiece_compliance(p), 1.0, 0.2);
    ASSERT_TRUE(lim.critical_gain);
    process::SimulationOptions o;
    o.duration = 40 * 0.2;
    const auto under = process::simulate_chatter(p, cut, 0.95 * *lim.critical_gain, o);
    const auto over = process::simulate_chatter(p, cut, 1.05 * *lim.critical_gain, o);
    EXPECT_LT(under.growth_per_revolution, 1.0);
    EXPECT_GT(over.growth_per_revolution, 1.0);
    // the amplitudes say the same without the summary
    EXPECT_LT(under.revolution_amplitude.back(), under.revolution_amplitude[1]);
    EXPECT_GT(over.revolution_amplitude.back(), over.revolution_amplitude[1]);
    EXPECT_NEAR(over.frequency, lim.chatter_frequency, 0.01 * lim.chatter_frequency);
  }
}

TEST(ChatterSimulation, WithoutOverlapTheCutSettles) {
  // mu = 0: M x'' + ... = K_c (U0 - x_w): the equilibrium X_w = K_c U0 g0 / (1 + K_c g0), g0 = 1/K_m + 1/K_w,
  // reached under heavy damping
  const process::TwoMassStructure p{1.0, 400.0, 1e5, 0.5, 300.0, 2e5};
  process::Cut cut;
  cut.overlap = 0.0;
  cut.revolution_period = 0.05;
  cut.depth = 2e-3;
  const double kc = 3e4, g0 = 1.0 / 1e5 + 1.0 / 2e5;
  process::SimulationOptions o;
  o.duration = 2.0;
  const auto r = process::simulate_chatter(p, cut, kc, o);
  EXPECT_NEAR(r.samples.back().x_w, kc * 2e-3 * g0 / (1.0 + kc * g0), 1e-9);
  EXPECT_NEAR(r.samples.back().force, kc * (2e-3 - r.samples.back().x_w), 1e-6);
  // the machine carries the whole force through its spring: x_m = F / K_m
  EXPECT_NEAR(r.samples.back().x_m, r.samples.back().force / 1e5, 1e-9);
}

TEST(ChatterSimulation, NoCuttingGainNoMotion) {
  // K_c = 0: no force ever acts, the structure stays at rest
  const process::TwoMassStructure p{0.03, 0.1, 120000.0, 0.09, 0.01, 12000.0};
  process::Cut cut;
  cut.revolution_period = 0.2;
  const auto r = process::simulate_chatter(p, cut, 0.0, {});
  for (const auto& s : r.samples) EXPECT_EQ(s.x_w, 0.0);
}

TEST(ChatterSimulation, RefusesANegativeGain) {
  process::Cut cut;
  cut.revolution_period = 0.2;
  EXPECT_THROW(process::simulate_chatter(dunckley_structure(kDunckleyCases[0]), cut, -1.0, {}), InputError);
}

}  // namespace tu_process_test_simulate
}  // namespace polarcam::test
