// Process monitoring: tooth-period averages with a fractional number of samples per tooth against the integral of
// a ramp done here; first, second and normalised differences of a hand-made sequence; the Welch PSD against
// Parseval; and on generated milling forces (fixed seeds): a broken tooth found within one revolution of its
// first pass, the same cut without the breakage (run-out and noise) raising no event, chatter found at its
// frequency and not confused with a breakage's spindle harmonics, an overload.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "cam/error.hpp"
#include "process/milling_signal.hpp"
#include "process/monitor.hpp"

namespace polarcam::test {
namespace tu_process_test_monitor {  // named: the test files compile together

using process::EventKind;

// The integral of floor(u) from 0 to b: the ramp x[k] = k held over each sample.
double ramp_integral(double b) {
  const double f = std::floor(b);
  return f * (f - 1) / 2 + f * (b - f);
}

TEST(ToothAverages, FractionalSamplesPerTooth) {
  std::vector<double> x(1000);
  for (size_t k = 0; k < x.size(); ++k) x[k] = static_cast<double>(k);
  // 617 rpm, 7 teeth, 1 kHz: P = 1000 / (617 / 60 * 7) = 13.8919... samples
  const double fs = 1000, n = 617.0 / 60.0;
  const int Z = 7;
  const double P = fs / (n * Z);
  const auto p = process::tooth_period_averages(x, fs, n, Z);
  ASSERT_EQ(p.size(), static_cast<size_t>(std::floor(1000 / P)));
  for (size_t i = 0; i < p.size(); ++i) {
    const double a = i * P, b = (i + 1) * P;
    EXPECT_NEAR(p[i].mean, (ramp_integral(b) - ramp_integral(a)) / P, 1e-9) << i;
    EXPECT_NEAR(p[i].end_s - p[i].start_s, 1.0 / (n * Z), 1e-12);
  }
  EXPECT_THROW(process::tooth_period_averages(x, fs, n, 0), InputError);
  EXPECT_THROW(process::tooth_period_averages(x, 10.0, n, Z), InputError);  // under two samples per tooth
}

TEST(ToothAverages, Differences) {
  std::vector<process::ToothPeriod> p;
  for (double v : {1.0, 1.0, 1.0, 0.0, 2.0, 1.0}) p.push_back({0, 0, v});
  const auto d = process::tooth_differences(p, 0.1);
  const std::vector<double> d1{0, 0, -1, 2, -1}, d2{0, 0, -1, 3, -3}, nd{0, 0, -1, 2 / 0.1, -0.5};
  EXPECT_EQ(d.d1, d1);
  EXPECT_EQ(d.d2, d2);
  ASSERT_EQ(d.normalised.size(), nd.size());
  for (size_t i = 0; i < nd.size(); ++i) EXPECT_NEAR(d.normalised[i], nd[i], 1e-12) << i;
}

TEST(Welch, SinePowerAndFrequency) {
  const double fs = 1000, A = 3.0, f0 = 125.0;  // f0 on bin 128 of 1024
  std::vector<double> x(8192);
  for (size_t k = 0; k < x.size(); ++k) x[k] = 7.0 + A * std::sin(2 * std::numbers::pi * f0 * k / fs);
  const auto psd = process::welch_psd(x, fs, 1024);
  ASSERT_EQ(psd.size(), 513u);
  double total = 0;
  size_t peak = 0;
  for (size_t k = 0; k < psd.size(); ++k) {
    total += psd[k] * fs / 1024;
    if (psd[k] > psd[peak]) peak = k;
  }
  EXPECT_EQ(peak, 128u);
  EXPECT_NEAR(total, A * A / 2, 1e-3 * A * A / 2);  // the variance (the mean removed)
}

process::MillingSignalOptions cut(uint64_t seed = 7) {
  process::MillingSignalOptions g;
  g.duration_s = 8.0;
  g.sample_rate_hz = 500.0;
  g.spindle_rev_per_s = 10.0;  // 600 rpm
  g.teeth = 4;
  g.engagement = 0.25;
  g.peak_force_N = 500.0;
  g.runout = 0.1;
  g.noise_N = 10.0;
  g.seed = seed;
  return g;
}

process::MonitorOptions options(const process::MillingSignalOptions& g) {
  process::MonitorOptions o;
  o.sample_rate_hz = g.sample_rate_hz;
  o.spindle_rev_per_s = g.spindle_rev_per_s;
  o.teeth = g.teeth;
  return o;
}

std::vector<process::MonitorEvent> of_kind(const process::MonitorResult& r, EventKind k) {
  std::vector<process::MonitorEvent> out;
  for (const auto& e : r.events)
    if (e.kind == k) out.push_back(e);
  return out;
}

TEST(Generator, ToothAveragesOfACleanCut) {
  auto g = cut();
  g.runout = 0.0;
  g.noise_N = 0.0;
  g.sample_rate_hz = 4000.0;
  const auto s = process::milling_force_signal(g);
  const auto p = process::tooth_period_averages(s.columns[0], g.sample_rate_hz, g.spindle_rev_per_s, g.teeth);
  // one half-sine pulse of 500 N per tooth period: mean 500 * 2 / pi (to the sampling's resolution)
  for (size_t i = 1; i < p.size(); ++i) EXPECT_NEAR(p[i].mean, 500.0 * 2 / std::numbers::pi, 0.5) << i;
  // the same seed, the same samples
  EXPECT_EQ(process::milling_force_signal(cut(3)).columns, process::milling_force_signal(cut(3)).columns);
  EXPECT_NE(process::milling_force_signal(cut(3)).columns, process::milling_force_signal(cut(4)).columns);
}

TEST(Monitor, CleanCutRaisesNoEvent) {
  for (uint64_t seed : {1, 2, 3, 4, 5}) {
    const auto g = cut(seed);
    const auto r = process::monitor_signal(process::milling_force_signal(g).columns[0], options(g));
    EXPECT_TRUE(r.events.empty()) << "seed " << seed << ": " << process::to_string(r.events.front().kind) << " at "
                                  << r.events.front().time_s << " value " << r.events.front().value;
    // the run-out shows in the learned differences: h = f_z + r_j - r_(j-1) varies by up to 2 * 0.1 * sin(45 deg)
    EXPECT_GT(r.learned_max_normalised, 0.05);
    EXPECT_LT(r.learned_max_normalised, 0.5);
    EXPECT_EQ(r.chatter_blocks, 3u);  // 8 s in blocks of 2.5 * 512 samples at 500 Hz
  }
}

TEST(Monitor, BrokenToothFoundWithinOneRevolution) {
  const double tooth = 1.0 / 40.0, rev = 0.1;
  for (double tb : {1.0, 1.013, 1.05, 1.0999, 2.37}) {
    for (int broken : {0, 2}) {
      auto g = cut(11);
      g.break_at_s = tb;
      g.broken_tooth = broken;
      const auto r = process::monitor_signal(process::milling_force_signal(g).columns[0], options(g));
      const auto br = of_kind(r, EventKind::breakage);
      ASSERT_EQ(br.size(), 1u) << tb << " " << broken;
      // the broken tooth's first pass at or after t_b
      long k = static_cast<long>(std::ceil(tb / tooth - 1e-9));
      while (k % 4 != broken) ++k;
      const double first = k * tooth;
      EXPECT_GE(br[0].time_s, first) << tb;
      EXPECT_LE(br[0].time_s, first + rev) << tb;
      EXPECT_LE(br[0].time_s, tb + rev + tooth) << tb;
      EXPECT_GT(std::abs(br[0].value), br[0].threshold);
      EXPECT_TRUE(of_kind(r, EventKind::chatter).empty()) << "a breakage's harmonics are not chatter";
    }
  }
}

TEST(Monitor, BrokenToothWithAFractionalToothPeriod) {
  auto g = cut(5);
  g.spindle_rev_per_s = 617.0 / 60.0;
  g.teeth = 7;
  g.engagement = 1.0 / 7.0;
  g.sample_rate_hz = 1000.0;
  g.duration_s = 3.0;
  g.break_at_s = 1.5;
  g.broken_tooth = 3;
  auto o = options(g);
  o.chatter = false;
  const auto r = process::monitor_signal(process::milling_force_signal(g).columns[0], o);
  const auto br = of_kind(r, EventKind::breakage);
  ASSERT_EQ(br.size(), 1u);
  EXPECT_GE(br[0].time_s, 1.5);
  EXPECT_LE(br[0].time_s, 1.5 + 60.0 / 617.0 + 60.0 / 617.0 / 7.0);
  // without the breakage: nothing
  g.break_at_s.reset();
  EXPECT_TRUE(process::monitor_signal(process::milling_force_signal(g).columns[0], o).events.empty());
}

TEST(Monitor, FussellRuleAlsoFindsTheBreakage) {
  auto g = cut(12);
  g.break_at_s = 3.0;
  auto o = options(g);
  o.rule = process::BreakageRule::fussell;
  const auto br = of_kind(process::monitor_signal(process::milling_force_signal(g).columns[0], o), EventKind::breakage);
  ASSERT_EQ(br.size(), 1u);
  EXPECT_GE(br[0].time_s, 3.0);
  EXPECT_LE(br[0].time_s, 3.0 + 0.1 + 0.025);
}

TEST(Monitor, ChatterFoundAtItsFrequency) {
  for (double fc : {173.0, 67.0, 126.3}) {
    auto g = cut(21);
    g.chatter_at_s = 3.0;
    g.chatter_frequency_hz = fc;
    // stronger than the tooth frequency's component (about 212 N: the half-sine pulses' fundamental), as Eq. 24
    // asks of chatter
    g.chatter_force_N = 300.0;
    const auto r = process::monitor_signal(process::milling_force_signal(g).columns[0], options(g));
    const auto ch = of_kind(r, EventKind::chatter);
    ASSERT_EQ(ch.size(), 1u) << fc;
    EXPECT_NEAR(ch[0].frequency_hz, fc, 500.0 / 512) << fc;  // within a bin
    EXPECT_GT(ch[0].time_s, 3.0);
    EXPECT_LE(ch[0].time_s - r.chatter_block_s, 3.0);  // the block that holds its start
    EXPECT_GT(ch[0].value, ch[0].threshold);
    EXPECT_TRUE(of_kind(r, EventKind::breakage).empty()) << fc;
  }
}

TEST(Monitor, WeakOscillationIsNotChatter) {
  // a component off the harmonics but too small to raise the amplitude over the set point (Eq. 22)
  auto g = cut(22);
  g.chatter_at_s = 3.0;
  g.chatter_frequency_hz = 173.0;
  g.chatter_force_N = 20.0;
  const auto r = process::monitor_signal(process::milling_force_signal(g).columns[0], options(g));
  EXPECT_TRUE(r.events.empty());
}

TEST(Monitor, Overload) {
  const auto g = cut(2);
  auto o = options(g);
  // a tooth period's mean is 500 * 2 / pi = 318 N times its chip, 1 + r_j - r_(j-1) feeds: 1.1 for teeth 0 and 3,
  // 0.9 for teeth 1 and 2 (350 N and 286 N); the first pass cuts one feed
  o.overload = 330.0;
  const auto r = process::monitor_signal(process::milling_force_signal(g).columns[0], o);
  const auto ov = of_kind(r, EventKind::overload);
  ASSERT_EQ(ov.size(), 1u);  // one event: every other tooth period, merged
  EXPECT_GE(ov[0].count, 159);
  EXPECT_LE(ov[0].count, 160);
  o.overload = 400.0;
  EXPECT_TRUE(process::monitor_signal(process::milling_force_signal(g).columns[0], o).events.empty());
}

TEST(Monitor, RefusesTooShortARecord) {
  auto g = cut();
  g.duration_s = 0.3;  // three learning revolutions and nothing after
  try {
    process::monitor_signal(process::milling_force_signal(g).columns[0], options(g));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "--learn-revolutions");
  }
}

}  // namespace tu_process_test_monitor
}  // namespace polarcam::test

namespace polarcam::test {
namespace tu_process_test_monitor {  // named: the test files compile together

TEST(SelectSignal, DefaultColumnQuantityAndEstimate) {
  process::SignalRecord r;
  r.period_s = 1e-3;
  r.names = {"speed_rad_per_s", "current_A"};
  r.columns = {{2, 2, 2}, {5, 5, 5}};
  auto s = process::select_signal(r, "f.csv", "", false);
  EXPECT_EQ(s.name, "current_A");  // no force_N: the current
  EXPECT_EQ(s.quantity, "current");
  EXPECT_DOUBLE_EQ(s.sample_rate_hz, 1000.0);
  s = process::select_signal(r, "f.csv", "speed_rad_per_s", false);
  EXPECT_EQ(s.quantity, "");
  // Eq. 3.36 in a steady state: F = 1058 (K_t I_a - B W), one sample shorter
  s = process::select_signal(r, "f.csv", "", true, 0.196);
  EXPECT_EQ(s.name, "estimated_force_N");
  ASSERT_EQ(s.x.size(), 2u);
  EXPECT_NEAR(s.x[0], 1058.0 * (0.3 * 5 - 0.196 * 2), 1e-6);
  try {
    process::select_signal(r, "f.csv", "force_N", false);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "--signal");
  }
  r.names = {"force_N", "x"};
  EXPECT_EQ(process::select_signal(r, "f.csv", "", false).name, "force_N");
  try {
    process::select_signal(r, "f.csv", "", true);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "f.csv");
  }
}

}  // namespace tu_process_test_monitor
}  // namespace polarcam::test
