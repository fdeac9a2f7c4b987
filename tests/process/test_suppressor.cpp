// The stepper chatter suppressor of A. B. Dunckley (1978), Ch. 3 and Sec. 5.4, in the regenerative loop: without
// steps it is the chatter simulation; the discrete model is the continuous one sampled; above the critical gain the
// cut that chatters without it is held with it (Sec. 3.3, Figs. 3.9-3.12) unless the model's frequency is 5 % high
// (Fig. 3.14); the tool is always a whole number of steps from where it started, the steps of a period are evenly
// spaced over it (Eq. 5.3), no period has more than the stepper's rate allows, and the steps add up to the final
// position.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <map>

#include "cam/error.hpp"
#include "process/simulate.hpp"
#include "process/stability.hpp"
#include "process/suppressor.hpp"
#include "tests/process/dunckley_cases.hpp"

namespace polarcam::test {
namespace tu_process_test_suppressor {  // named: the test files compile together

// The suppression simulation of Sec. 3.3 and App. B.5: U0 = 0.02, S_s = 0.00067; a sample period of 1 ms and a
// stepper that allows 5 steps a period.
process::SuppressorSpec spec_b5() {
  process::SuppressorSpec s;
  s.sample_period = 1e-3;
  s.step_size = 0.00067;
  s.max_step_rate = 5000.0;
  return s;
}

process::Cut cut_b5() {
  process::Cut c;
  c.overlap = 1.0;
  c.revolution_period = 0.2;
  c.depth = 0.02;
  return c;
}

double limit_of(const process::TwoMassStructure& p) {
  return *process::nyquist_limit(process::workpiece_compliance(p), 1.0, 0.2).critical_gain;
}

process::SimulationOptions revolutions(int n) {
  process::SimulationOptions o;
  o.duration = n * 0.2;
  return o;
}

TEST(Suppressor, WithoutStepsItIsTheChatterSimulation) {
  // a step of 1 m: the prediction (a few mm) always rounds to position 0, so the tool never moves and the cut is the
  // one simulate_chatter integrates; the integrator only splits its steps at the sampling instants
  const process::TwoMassStructure p = dunckley_structure(kDunckleyCases[1]);  // system 2
  const double kc = 1.05 * limit_of(p);
  process::SuppressorSpec s = spec_b5();
  s.step_size = 1.0;
  const auto plain = process::simulate_chatter(p, cut_b5(), kc, revolutions(10));
  const auto run = process::simulate_suppression(p, cut_b5(), kc, s, revolutions(10));
  EXPECT_TRUE(run.steps.empty());
  EXPECT_EQ(run.final_position, 0);
  // the run without the suppressor is simulate_chatter's, number for number
  ASSERT_EQ(run.without.samples.size(), plain.samples.size());
  for (size_t i = 0; i < plain.samples.size(); ++i) {
    EXPECT_EQ(run.without.samples[i].x_w, plain.samples[i].x_w);
    EXPECT_EQ(run.without.samples[i].force, plain.samples[i].force);
  }
  EXPECT_EQ(run.without.growth_per_revolution, plain.growth_per_revolution);
  // and the run with a suppressor that never steps agrees with it to rounding
  ASSERT_EQ(run.with.samples.size(), plain.samples.size());
  double scale = 0.0, worst = 0.0;
  for (size_t i = 0; i < plain.samples.size(); ++i) {
    scale = std::max(scale, std::abs(plain.samples[i].x_w));
    worst = std::max(worst, std::abs(run.with.samples[i].x_w - plain.samples[i].x_w));
    EXPECT_EQ(run.with.samples[i].x_t, 0.0);
  }
  EXPECT_LT(worst, 1e-9 * scale);
  EXPECT_NEAR(run.with.growth_per_revolution, plain.growth_per_revolution, 1e-9);
  EXPECT_GT(plain.growth_per_revolution, 1.0);  // the cut chatters: the comparison is of a growing vibration
}

TEST(Suppressor, TheToolsDisplacementEntersTheCut) {
  // without overlap (mu = 0) and with heavy damping the cut settles: F = K_c (U0 - X_w + X_t), X_w = F g0,
  // g0 = 1/K_m + 1/K_w; with the tool at its final q steps, X_w = K_c (U0 + q S) g0 / (1 + K_c g0)
  const process::TwoMassStructure p{1.0, 400.0, 1e5, 0.5, 300.0, 2e5};
  process::Cut cut;
  cut.overlap = 0.0;
  cut.revolution_period = 0.05;
  cut.depth = 2e-3;
  const double kc = 3e4, g0 = 1.0 / 1e5 + 1.0 / 2e5, S = 1e-5;
  process::SuppressorSpec s;
  s.sample_period = 1e-3;
  s.step_size = S;
  s.max_step_rate = 1e5;
  s.source = process::ModelSource::given;
  s.omega_n = 300.0;
  s.zeta = 0.7;
  s.gain = g0;
  process::SimulationOptions o;
  o.duration = 2.0;
  const auto run = process::simulate_suppression(p, cut, kc, s, o);
  const double q = static_cast<double>(run.final_position);
  EXPECT_GT(q, 50.0);  // the tool moved
  const auto& last = run.with.samples.back();
  EXPECT_NEAR(last.x_t, q * S, 1e-15);
  EXPECT_NEAR(last.x_w, kc * (2e-3 + q * S) * g0 / (1.0 + kc * g0), 1e-9);
  EXPECT_NEAR(last.force, kc * (2e-3 - last.x_w + last.x_t), 1e-6);
}

TEST(Suppressor, ZeroOrderHoldModelIsTheContinuousStepResponseSampled) {
  // G(s) = K w^2 / (s^2 + 2 zeta w s + w^2) driven by a unit step held from t = 0: the discrete model's output at
  // sample k is the continuous step response K (1 - e^{-sigma t} (cos w_d t + sigma / w_d sin w_d t)) at t = k T_s
  const double wn = 350.0, zeta = 0.05, K = 2e-4, Ts = 1.3e-3;
  const auto m = process::zoh_second_order(wn, zeta, K, Ts);
  const double sigma = zeta * wn, wd = wn * std::sqrt(1.0 - zeta * zeta);
  double y1 = 0.0, y2 = 0.0;  // y(k-1), y(k-2)
  for (int k = 1; k <= 200; ++k) {
    const double u1 = 1.0, u2 = k >= 2 ? 1.0 : 0.0;  // the input one and two samples back
    const double y = m.A1 * u1 + m.A2 * u2 - m.B1 * y1 - m.B2 * y2;
    const double t = k * Ts;
    const double exact = K * (1.0 - std::exp(-sigma * t) * (std::cos(wd * t) + sigma / wd * std::sin(wd * t)));
    EXPECT_NEAR(y, exact, 1e-12 * K) << "sample " << k;
    y2 = y1;
    y1 = y;
  }
  EXPECT_NEAR((m.A1 + m.A2) / (1.0 + m.B1 + m.B2), K, 1e-12 * K);
}

TEST(Suppressor, StructureModelIsTheMajorLoop) {
  // Sec. 3.3's 'best' model: its polar plot coincides with the structure's largest loop; at the loop's resonance
  // the model's response K / (2 j zeta) and the structure's G(j w_n) agree, and the model sits on the lower mode
  for (int i : {0, 1}) {  // systems 1 and 2
    const process::TwoMassStructure p = dunckley_structure(kDunckleyCases[i]);
    const auto m = process::structure_model(p, 1e-3);
    const double lower = process::undamped_frequencies(p)[0];
    EXPECT_NEAR(m.omega_n, lower, 1e-3 * lower);
    const std::complex<double> g = process::workpiece_compliance(p).at(m.omega_n);
    const std::complex<double> model = m.gain / std::complex<double>(0.0, 2.0 * m.zeta);
    EXPECT_LT(std::abs(g - model), 0.02 * std::abs(model)) << "system " << kDunckleyCases[i].system;
  }
}

struct HeldCase {
  int index;      // into kDunckleyCases
  double factor;  // K_c over the Nyquist limit
};

TEST(Suppressor, HoldsACutThreeAndFiveTimesOverTheLimit) {
  // Sec. 3.3 (Figs. 3.9-3.12): systems 1 and 2 at 3 and 5 times their limits, 'best' model: "although there is some
  // vibration present, the systems have not become unstable"
  for (HeldCase hc : {HeldCase{0, 3.0}, HeldCase{0, 5.0}, HeldCase{1, 3.0}, HeldCase{1, 5.0}}) {
    const process::TwoMassStructure p = dunckley_structure(kDunckleyCases[hc.index]);
    SCOPED_TRACE("system " + std::to_string(kDunckleyCases[hc.index].system) + " at " + std::to_string(hc.factor));
    const auto run = process::simulate_suppression(p, cut_b5(), hc.factor * limit_of(p), spec_b5(), revolutions(10));
    // without: chatter, the vibration at least doubling every revolution
    EXPECT_GT(run.without.growth_per_revolution, 2.0);
    // with: X_w no larger in the last revolution than in the first (the ring of the cut's start, which the
    // structure's own damping barely decays), and the relative displacement the cut sees within 1.5 steps
    const auto& with = run.with.revolution_half_range;
    EXPECT_LT(with.back(), 1.05 * with.front());
    EXPECT_LT(run.with.revolution_relative_half_range.back(), 1.5 * 0.00067);
    EXPECT_LT(run.with.growth_per_revolution, 1.01);
    EXPECT_EQ(run.saturated_periods, 0);
    // the reduction after 10 revolutions: more than a thousand times
    EXPECT_GT(run.without.revolution_half_range.back() / with.back(), 1e3);
  }
}

TEST(Suppressor, AModelFivePercentHighChatters) {
  // Sec. 3.3, Fig. 3.14: system 1 at 3 times its limit with the model's natural frequency 5 % above the 'best':
  // "severely unstable"
  const process::TwoMassStructure p = dunckley_structure(kDunckleyCases[0]);
  process::SuppressorSpec s = spec_b5();
  s.model_frequency_scale = 1.05;
  const auto run = process::simulate_suppression(p, cut_b5(), 3.0 * limit_of(p), s, revolutions(6));
  EXPECT_GT(run.with.growth_per_revolution, 2.0);
  EXPECT_GT(run.with.revolution_relative_half_range.back(), 100.0 * 0.00067);
}

TEST(Suppressor, WholeStepsEvenlySpacedAndConserved) {
  const process::TwoMassStructure p = dunckley_structure(kDunckleyCases[0]);
  const process::SuppressorSpec s = spec_b5();
  const auto run = process::simulate_suppression(p, cut_b5(), 3.0 * limit_of(p), s, revolutions(5));
  ASSERT_GT(run.steps.size(), 100u);
  // the tool is always a whole number of steps from its start
  for (const auto& smp : run.with.samples) {
    const double q = smp.x_t / s.step_size;
    EXPECT_NEAR(q, std::round(q), 1e-9) << "t = " << smp.t;
  }
  // conservation: the signed steps add up to the final position, each step moves the position by its direction
  long long sum = 0, prev = 0;
  for (const auto& st : run.steps) {
    ASSERT_TRUE(st.dir == 1 || st.dir == -1);
    sum += st.dir;
    EXPECT_EQ(st.position, prev + st.dir);
    prev = st.position;
  }
  EXPECT_EQ(sum, run.final_position);
  EXPECT_EQ(run.steps_forward - run.steps_reverse, run.final_position);
  EXPECT_EQ(run.steps_forward + run.steps_reverse, static_cast<long long>(run.steps.size()));
  // the last sample's tool displacement is the final position
  EXPECT_NEAR(run.with.samples.back().x_t, static_cast<double>(run.final_position) * s.step_size, 1e-12);
  // each period's N steps at k T_s + (j + 1/2) T_s / N, all in one direction, N within the stepper's rate
  std::map<long long, std::vector<const process::PositionerStep*>> by_period;
  for (const auto& st : run.steps) by_period[static_cast<long long>(std::floor(st.t / s.sample_period))].push_back(&st);
  long long most = 0;
  for (const auto& [k, steps] : by_period) {
    const auto n = static_cast<long long>(steps.size());
    most = std::max(most, n);
    EXPECT_LE(n, 5);
    for (long long j = 0; j < n; ++j) {
      const double expected = (static_cast<double>(k) + (static_cast<double>(j) + 0.5) / static_cast<double>(n)) * 1e-3;
      EXPECT_NEAR(steps[static_cast<size_t>(j)]->t, expected, 1e-14) << "period " << k << " step " << j;
      EXPECT_EQ(steps[static_cast<size_t>(j)]->dir, steps[0]->dir);
      if (j > 0) {
        EXPECT_NEAR(steps[static_cast<size_t>(j)]->t - steps[static_cast<size_t>(j - 1)]->t,
                    1e-3 / static_cast<double>(n), 1e-14);
      }
    }
  }
  EXPECT_EQ(most, run.max_steps_in_period);
  EXPECT_DOUBLE_EQ(run.max_step_rate_used, static_cast<double>(most) / 1e-3);
}

TEST(Suppressor, ASlowStepperSaturatesAndSaysSo) {
  // one step a period at most: the cut needs two at times, so some periods fall short (and are counted), no
  // period has more than one step, and the positions still add up
  const process::TwoMassStructure p = dunckley_structure(kDunckleyCases[0]);
  process::SuppressorSpec s = spec_b5();
  s.max_step_rate = 1000.0;
  const auto run = process::simulate_suppression(p, cut_b5(), 3.0 * limit_of(p), s, revolutions(5));
  EXPECT_GT(run.saturated_periods, 0);
  ASSERT_TRUE(run.first_saturation.has_value());
  EXPECT_GE(run.max_shortfall, 1);
  EXPECT_EQ(run.max_steps_in_period, 1);
  EXPECT_EQ(run.steps_per_period_limit, 1);
  EXPECT_DOUBLE_EQ(run.max_step_rate_used, 1000.0);
  std::map<long long, int> per_period;
  for (const auto& st : run.steps) EXPECT_LE(++per_period[static_cast<long long>(std::floor(st.t / 1e-3))], 1);
  // the first saturated period starts at a sampling instant
  EXPECT_NEAR(*run.first_saturation / 1e-3, std::round(*run.first_saturation / 1e-3), 1e-9);
  long long sum = 0;
  for (const auto& st : run.steps) sum += st.dir;
  EXPECT_EQ(sum, run.final_position);
}

TEST(Suppressor, RefusesWhatCannotRun) {
  const process::TwoMassStructure p = dunckley_structure(kDunckleyCases[0]);
  auto refused = [&](process::SuppressorSpec s, const std::string& key) {
    try {
      process::simulate_suppression(p, cut_b5(), 100.0, s, revolutions(1));
    } catch (const InputError& e) {
      EXPECT_EQ(e.place(), key);
      return;
    }
    ADD_FAILURE() << "accepted, expected a refusal naming " << key;
  };
  process::SuppressorSpec s = spec_b5();
  s.max_step_rate = 500.0;  // half a step per 1 ms period
  refused(s, "suppressor.max_step_rate");
  s = spec_b5();
  s.step_size = 0.0;
  refused(s, "suppressor.step_size");
  s = spec_b5();
  s.source = process::ModelSource::discrete;
  s.A1 = 1e-5;
  s.B1 = -1.0;
  s.B2 = 1.2;  // a pole outside the unit circle
  refused(s, "suppressor.model");
  s = spec_b5();
  s.source = process::ModelSource::given;
  s.omega_n = 350.0;
  s.zeta = 1.5;
  s.gain = 1e-4;
  refused(s, "suppressor.zeta");
}

TEST(Suppressor, GivenAndDiscreteModelsAreTheSameModel) {
  // the structure model's coefficients given back as a discrete model, or its w_n, zeta and gain given, issue the
  // same steps
  const process::TwoMassStructure p = dunckley_structure(kDunckleyCases[1]);
  const auto m = process::structure_model(p, 1e-3);
  process::SuppressorSpec g = spec_b5(), d = spec_b5();
  g.source = process::ModelSource::given;
  g.omega_n = m.omega_n;
  g.zeta = m.zeta;
  g.gain = m.gain;
  d.source = process::ModelSource::discrete;
  d.A1 = m.A1;
  d.A2 = m.A2;
  d.B1 = m.B1;
  d.B2 = m.B2;
  const double kc = 3.0 * limit_of(p);
  const auto a = process::simulate_suppression(p, cut_b5(), kc, spec_b5(), revolutions(3));
  const auto b = process::simulate_suppression(p, cut_b5(), kc, g, revolutions(3));
  const auto c = process::simulate_suppression(p, cut_b5(), kc, d, revolutions(3));
  ASSERT_EQ(a.steps.size(), b.steps.size());
  ASSERT_EQ(a.steps.size(), c.steps.size());
  for (size_t i = 0; i < a.steps.size(); ++i) {
    EXPECT_EQ(a.steps[i].t, b.steps[i].t);
    EXPECT_EQ(a.steps[i].t, c.steps[i].t);
    EXPECT_EQ(a.steps[i].position, c.steps[i].position);
  }
  // the discrete model's w_n, zeta and gain read back from its coefficients
  EXPECT_NEAR(c.model.omega_n, m.omega_n, 1e-9 * m.omega_n);
  EXPECT_NEAR(c.model.zeta, m.zeta, 1e-6 * m.zeta);
  EXPECT_NEAR(c.model.gain, m.gain, 1e-9 * std::abs(m.gain));
}

}  // namespace tu_process_test_suppressor
}  // namespace polarcam::test
