// The event-band feed controller of Fussell & Gagne 1991 (Sec. V-VI): the feeds it reaches with the bands of
// Tables 2-4 and the limit cycle at a high effective gain.
#include <gtest/gtest.h>

#include <numbers>

#include "cam/error.hpp"
#include "process/band_control.hpp"
#include "process/sim_file.hpp"

namespace tu_process_test_band_control {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::process;

namespace {
constexpr double kIn = 0.0254, kLbf = 4.4482216152605, kInPerMin = 0.0254 / 60;

// Table 1's tool (4 flutes, 2000 rpm) in a cut with the lumped force F = k a b f_t, k = 180 N/mm^3.
BandSettings cut(double lb_total_lo, double lb_total_hi, double ft_lo_in, double ft_hi_in, double lb_perp_lo,
                 double lb_perp_hi, double a_in, double b_in, double b2_in, double ratio, double programmed_in_min) {
  BandSettings s;
  s.bands = {{"shank failure", BandQuantity::total_force, lb_total_lo * kLbf, lb_total_hi * kLbf, {}},
             {"tooth failure", BandQuantity::feed_per_tooth, ft_lo_in * kIn, ft_hi_in * kIn, {}},
             {"tool deflection", BandQuantity::perpendicular_force, lb_perp_lo * kLbf, lb_perp_hi * kLbf, {}}};
  s.programmed_feed = programmed_in_min * kInPerMin;
  s.cut.teeth = 4;
  s.cut.spindle_speed_rad_s = 2000 * 2 * std::numbers::pi / 60;
  s.cut.specific_force = 180e9;
  s.cut.radial_depth = a_in * kIn;
  s.cut.axial_depth = b_in * kIn;
  s.cut.step_time = 2.0;
  s.cut.step_axial_depth = b2_in * kIn;
  s.cut.perpendicular_ratio = ratio;
  s.duration_s = 5.0;
  return s;
}
// Eq. 19: the feed (in/min) at a feed per tooth (in): f_t * 4 teeth * 2000 rpm.
double feed_in_min(double ft_in) { return ft_in * 4 * 2000; }
}  // namespace

// Trial one (Tables 1-2, Fig. 8): before the depth step the tooth band limits the feed: the feed per tooth
// inside 0.0030-0.0035 in, 24-28 in/min; after the step from 0.25 in to 0.5 in both forces rise above their
// bands and the feed falls until the perpendicular force is inside its band (100-130 lbf), where it holds.
TEST(ProcessBandControl, TrialOneReachesThePapersFeeds) {
  const BandSettings s = cut(150, 200, 0.0030, 0.0035, 100, 130, 0.25, 0.25, 0.5, 0.7, 30);
  const BandResult r = simulate_band_control(s);
  ASSERT_TRUE(r.settled_feed_before_step.has_value());
  const double f = *r.settled_feed_before_step / kInPerMin;
  EXPECT_GE(f, feed_in_min(0.0030));
  EXPECT_LE(f, feed_in_min(0.0035));
  // just before the step the tooth band holds; at the end the deflection band does
  const BandSample* before = nullptr;
  for (const auto& smp : r.series)
    if (smp.t < 2.0) before = &smp;
  ASSERT_NE(before, nullptr);
  EXPECT_EQ(before->active_event, 1);
  const BandSample& end = r.series.back();
  EXPECT_EQ(end.action, BandAction::hold);
  EXPECT_GE(end.perpendicular_force, 100 * kLbf);
  EXPECT_LE(end.perpendicular_force, 130 * kLbf);
  EXPECT_LE(end.total_force, 200 * kLbf);
  // the feed that puts the perpendicular force in its band: F_perp = 0.7 k a b f_t, at b = 0.5 in
  const double per_ft = 0.7 * 180e9 * 0.25 * kIn * 0.5 * kIn;  // N per m of feed per tooth
  EXPECT_GE(end.command / kInPerMin, feed_in_min(100 * kLbf / per_ft / kIn) * 0.99);
  EXPECT_LE(end.command / kInPerMin, feed_in_min(130 * kLbf / per_ft / kIn) * 1.01);
  EXPECT_FALSE(r.limit_cycle);
}

// Cut one (Table 3): a slot, 0.1 in deep then 0.25 in: the tooth band (0.00135-0.00165 in) limits the feed to
// 10.8-13.2 in/min before the step, the deflection band (45-55 lbf) after it.
TEST(ProcessBandControl, CutOneReachesThePapersFeeds) {
  const BandResult r = simulate_band_control(cut(180, 220, 0.00135, 0.00165, 45, 55, 0.5, 0.1, 0.25, 0.7, 20));
  ASSERT_TRUE(r.settled_feed_before_step.has_value());
  EXPECT_GE(*r.settled_feed_before_step / kInPerMin, feed_in_min(0.00135));
  EXPECT_LE(*r.settled_feed_before_step / kInPerMin, feed_in_min(0.00165));
  EXPECT_EQ(r.series.back().active_event, 2);
  EXPECT_LE(r.series.back().perpendicular_force, 55 * kLbf);
}

// The limit cycle (Sec. VI): stable at effective gains of 5, 10, 20 and 50 (in/min)/s with 0.15 in axial depth
// (slot, 0.5 in radial), a limit cycle at 50 (in/min)/s with 0.25 in. The report does not give the bands of
// these tests: here a 25 lbf total-force band (195-220 lbf) and Table 2's tooth band, 100 Hz, 50 in/min
// programmed, the gain set by the step (0.1 % to 1 %).
TEST(ProcessBandControl, LimitCycleAboveAGain) {
  auto run = [](double depth_in, double gain_in_min_s) {
    BandSettings s = cut(195, 220, 0.0030, 0.0035, 1000, 2000, 0.5, depth_in, depth_in, 0.0, 50);
    s.cut.step_time.reset();
    s.step_fraction = gain_in_min_s / 50 / 100;
    s.duration_s = 6.0;
    const BandResult r = simulate_band_control(s);
    EXPECT_NEAR(r.effective_gain / kInPerMin, gain_in_min_s, 1e-9);
    return r.limit_cycle;
  };
  for (double g : {5.0, 10.0, 20.0, 50.0}) EXPECT_FALSE(run(0.15, g)) << g;
  for (double g : {5.0, 10.0, 20.0}) EXPECT_FALSE(run(0.25, g)) << g;
  EXPECT_TRUE(run(0.25, 50.0));
  EXPECT_TRUE(run(0.25, 100.0));
}

// The rules: with every quantity below its band the override climbs one step per period to its maximum, and
// the time it takes is (max / step) periods.
TEST(ProcessBandControl, IncreasesOneStepPerPeriodWhenNoEventIsActive) {
  BandSettings s = cut(1e5, 2e5, 1, 2, 1e5, 2e5, 0.1, 0.1, 0.1, 0.5, 10);
  s.cut.step_time.reset();
  s.duration_s = 2.0;
  const BandResult r = simulate_band_control(s);
  // 1 % per 10 ms, the first step at t = 0: the command set at period i is (i + 1) %, 150 % from i = 149
  EXPECT_NEAR(r.series[99].command / kInPerMin, 10.0, 1e-9);
  EXPECT_NEAR(r.series[148].command / kInPerMin, 14.9, 1e-9);
  EXPECT_NEAR(r.series[149].command / kInPerMin, 15.0, 1e-9);
  EXPECT_NEAR(r.series[199].command / kInPerMin, 15.0, 1e-9);
  EXPECT_GT(r.override_limited_samples, 0);
}

TEST(ProcessBandControl, ToolLimitsBecomeHardLimits) {
  BandSettings s = cut(150, 200, 0.0030, 0.0035, 100, 130, 0.25, 0.25, 0.5, 0.7, 30);
  ToolLimits l;
  l.shank_force_limit_N = 210 * kLbf;
  apply_tool_limits(s, l);
  const BandResult r = simulate_band_control(s);
  // after the step the true total force reaches about 250 lbf before the feed comes down
  ASSERT_EQ(r.exceeded.size(), 1u);
  EXPECT_EQ(r.exceeded[0], "shank failure");
  l.shank_force_limit_N = 190 * kLbf;  // below the band's upper limit
  EXPECT_THROW(apply_tool_limits(s, l), InputError);
}

TEST(ProcessBandControl, BadSettingsAreRefused) {
  BandSettings s = cut(150, 200, 0.0030, 0.0035, 100, 130, 0.25, 0.25, 0.5, 0.7, 30);
  s.sim_rate_hz = 5050;  // not a whole multiple of 100 Hz
  EXPECT_THROW(simulate_band_control(s), InputError);
  s = cut(200, 150, 0.0030, 0.0035, 100, 130, 0.25, 0.25, 0.5, 0.7, 30);
  EXPECT_THROW(simulate_band_control(s), InputError);
}

// The simulation file: the report's units (in/min, lbf, in) into SI, the bands in their order, the tool file
// relative to the simulation file's folder.
TEST(ProcessBandControl, SimulationFile) {
  const std::string text = R"([controller]
programmed_feed = "30 in/min"
[cut]
teeth = 4
spindle_speed = "2000 rpm"
specific_force = "180 N/mm^3"
radial_depth = "0.25 in"
axial_depth = "0.25 in"
[simulation]
duration = "3 s"
[tool]
file = "tool.toml"
[[band]]
event = "shank failure"
quantity = "total_force"
lower = "150 lbf"
upper = "200 lbf"
[[band]]
event = "tooth failure"
quantity = "feed_per_tooth"
lower = "0.0030 in"
upper = "0.0035 in"
)";
  const BandProblem p = parse_band_toml(text, "dir/bands.toml");
  EXPECT_NEAR(p.settings.programmed_feed, 30 * kInPerMin, 1e-15);
  EXPECT_NEAR(p.settings.cut.specific_force, 1.8e11, 1e-3);
  ASSERT_EQ(p.settings.bands.size(), 2u);
  EXPECT_EQ(p.settings.bands[0].event, "shank failure");
  EXPECT_NEAR(p.settings.bands[0].upper, 200 * kLbf, 1e-9);
  EXPECT_EQ(p.settings.bands[1].quantity, BandQuantity::feed_per_tooth);
  EXPECT_NEAR(p.settings.bands[1].lower, 0.003 * kIn, 1e-15);
  EXPECT_EQ(*p.tool_file, "dir/tool.toml");
  EXPECT_EQ(p.settings.rate_hz, 100.0);         // the report's defaults
  EXPECT_EQ(p.settings.step_fraction, 0.01);
  try {
    parse_band_toml(std::string(text).replace(text.find("feed_per_tooth"), 14, "torque"), "b.toml");
    FAIL() << "an unknown quantity was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), "b.toml:20: key 'band.tooth failure.quantity'");
  }
}

}  // namespace tu_process_test_band_control
