// The time-optimal speed schedule (machine/dynamics/time_optimal): the squared-speed table's exact times, a circle
// about the pole whose fastest schedule is computed here by hand from the torque model (Eq. 5.15, 5.16), the
// checks the schedule must pass as analyze_torques measures them, and its local optimality.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "cam/curves.hpp"
#include "machine/dynamics/time_optimal.hpp"
#include "machine/dynamics/verdict.hpp"
#include "tests/dynamics_helpers.hpp"

namespace tu_machine_dynamics_test_time_optimal {  // the test files of a program compile together (unity build)

using namespace polarcam;
using namespace polarcam::test;

namespace {
constexpr double kPi = std::numbers::pi;

// Simpson's rule on [a, b] with n (even) intervals.
double simpson(const std::function<double(double)>& f, double a, double b, int n) {
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
  return sum * h / 3.0;
}

// The circle of radius R about the pole with a heavy carriage: the angular drive's step-rate limit caps the speed,
// its torque limits the acceleration and the braking.
struct CircleCase {
  static constexpr double R = 0.1, mass = 200.0, max_rate = 1500.0, SF = 1.2;
  Rig rig{make_circle({0, 0}, R), Placement{}, 0.01, inertial(mass)};
  CircleCase() { rig.machine.angular.max_step_rate = max_rate; }
  PlacedPath placed() const { return {rig.path.get(), &rig.track, 0.0, 1}; }
  TimeOptimalLimits limits(int stations = 4000) const {
    TimeOptimalLimits l;
    l.safety_factor = SF;
    l.stations = stations;
    return l;
  }
};

}  // namespace

TEST(SquaredSpeedTable, ConstantAccelerationTimesExactly) {
  // from rest at a = 2 m/s^2 over 1 m, then back to rest over 1 m: t = 2 sqrt(2 L / a)
  const double a = 2.0, vmax = std::sqrt(2.0 * a * 1.0);
  const SpeedProfilePtr p = make_table_speed_sq({{0.0, 0.0}, {0.5, std::sqrt(2 * a * 0.5)}, {1.0, vmax}, {2.0, 0.0}}, 2.0);
  EXPECT_NEAR(p->total_time(), 2.0 * std::sqrt(2.0 * 1.0 / a), 1e-12);
  EXPECT_NEAR(p->time_at(0.3), std::sqrt(2.0 * 0.3 / a), 1e-12);
  EXPECT_NEAR(p->speed_at(0.3), std::sqrt(2.0 * a * 0.3), 1e-12);
  EXPECT_NEAR(p->accel_at(0.7), a, 1e-12);
  EXPECT_NEAR(p->accel_at(1.5), -vmax * vmax / 2.0, 1e-12);
  EXPECT_EQ(p->kinks(), (std::vector<double>{0.5, 1.0}));
  EXPECT_THROW(make_table_speed_sq({{0.0, 0.0}, {1.0, 0.0}, {2.0, 1.0}}, 2.0), InputError);
  EXPECT_THROW(make_table_speed_sq({{0.0, 1.0}, {1.0, -1.0}}, 1.0), InputError);
  EXPECT_THROW(make_table_speed_sq({{0.0, 1.0}, {0.5, 1.0}}, 1.0), InputError);
}

TEST(TimeOptimal, CircleAboutThePoleByHand) {
  const CircleCase c;
  const MachineModel& m = c.rig.machine;
  const Mechanics& k = m.mech;
  const double M = k.carriage_mass + c.mass, R = c.R;
  // theta' = V / R: the angular motor steps at k_theta V / (2 pi R) * 400 per second
  const double rate_per_v = k.k_theta / (2 * kPi * R) * 400.0;
  const double V_cap = c.max_rate / rate_per_v;
  // T_theta = K1 [(J_A / R + M R) a_t + F_f L_A] within +-T_p(rate) / SF; T_R = -K2 M V^2 / R stays far inside
  const double inertia = k.arm_inertia / R + M * R;
  auto P = [&](double V) { return m.angular.pullout_at_rate(rate_per_v * V) / c.SF; };
  auto a_up = [&](double V) { return (P(V) / k.K1 - k.arm_friction_torque) / inertia; };
  auto a_down = [&](double V) { return (P(V) / k.K1 + k.arm_friction_torque) / inertia; };
  ASSERT_LT(k.K2 * M * V_cap * V_cap / R, m.radial.pullout_at_rate(0.0) / c.SF * 0.7);
  ASSERT_GT(a_up(V_cap), 0.1);
  // time and distance to reach V_cap from rest, and to stop from it: dt = dV / a, ds = V dV / a
  const int n = 20000;
  const double t_up = simpson([&](double V) { return 1.0 / a_up(V); }, 0.0, V_cap, n);
  const double s_up = simpson([&](double V) { return V / a_up(V); }, 0.0, V_cap, n);
  const double t_dn = simpson([&](double V) { return 1.0 / a_down(V); }, 0.0, V_cap, n);
  const double s_dn = simpson([&](double V) { return V / a_down(V); }, 0.0, V_cap, n);
  const double L = 2 * kPi * R;
  const double T_hand = t_up + t_dn + (L - s_up - s_dn) / V_cap;

  const TimeOptimalSchedule s = time_optimal_speed(c.placed(), m, c.rig.load, c.limits());
  // never faster than the optimum; slower by the planner's margin under each limit (2e-4) and the grid
  EXPECT_GE(s.total_time(), T_hand * (1 - 1e-5));
  EXPECT_LE(s.total_time(), T_hand * (1 + 6e-4));
  // the ramp: V^2 at 2 mm along the path against V(s) integrated by hand (ds = V dV / a_up)
  const double s_probe = 0.002;
  ASSERT_LT(s_probe, s_up);
  double lo = 0.0, hi = V_cap;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (simpson([&](double V) { return V / a_up(V); }, 0.0, mid, 2000) < s_probe ? lo : hi) = mid;
  }
  EXPECT_NEAR(s.profile->speed_at(s_probe), lo, 5e-3 * lo);
  // the stretches: accelerating by the angular torque, cruising at the angular step-rate limit, braking by the
  // angular torque
  ASSERT_GE(s.stretches.size(), 3u);
  EXPECT_EQ(s.stretches.front().phase, Phase::accelerate);
  EXPECT_EQ(s.stretches.front().binding, Binding::angular_torque);
  bool cruise = false;
  for (const auto& st : s.stretches)
    if (st.phase == Phase::limit && st.binding == Binding::angular_step_rate && st.s1 - st.s0 > 0.5 * L) cruise = true;
  EXPECT_TRUE(cruise);
  EXPECT_EQ(s.stretches.back().binding, Binding::angular_torque);
  EXPECT_EQ(s.stretches.back().phase, Phase::brake);
}

TEST(TimeOptimal, PassesTheTorqueAnalysisAndIsLocallyOptimal) {
  const CircleCase c;
  const TimeOptimalLimits lim = c.limits(800);
  const TimeOptimalSchedule s = time_optimal_speed(c.placed(), c.rig.machine, c.rig.load, lim);
  // the schedule's own check against an independent analysis at a denser sampling
  AnalysisOptions dense;
  dense.target_samples = 20000;
  const DynamicsInput in{c.rig.path.get(), &c.rig.track, 0.0, s.profile.get(), &c.rig.machine, &c.rig.load, 1};
  const TorqueAnalysis a = analyze_torques(in, dense);
  EXPECT_LE(worst_torque_ratio(a), 1.0 / lim.safety_factor + 1e-3);
  EXPECT_LE(a.angular.step_rate.value, CircleCase::max_rate * (1 + 1e-9));
  // the verdict of `analyze` at the limit plus the 1e-3 the schedule promises: GO, step rates included
  EXPECT_TRUE(judge(a, c.rig.machine, 1.0 / (1.0 / lim.safety_factor + 1e-3)).go);

  // raising V by 1 % at one station of a saturated stretch breaks a limit
  auto raised_fails = [&](size_t j) {
    std::vector<SpeedStation> st = s.stations;
    st[j].v *= 1.01;
    const SpeedProfilePtr p = make_table_speed_sq(st, s.profile->length());
    const DynamicsInput in2{c.rig.path.get(), &c.rig.track, 0.0, p.get(), &c.rig.machine, &c.rig.load, 1};
    const TorqueAnalysis b = analyze_torques(in2);
    return worst_torque_ratio(b) > 1.0 / lim.safety_factor + 1e-3 || b.angular.step_rate.value > CircleCase::max_rate;
  };
  int tried = 0;
  for (const ScheduleStretch& st : s.stretches) {
    for (double f : {0.25, 0.5, 0.75}) {
      const double at = st.s0 + f * (st.s1 - st.s0);
      const size_t j = static_cast<size_t>(std::lround(at / s.profile->length() * (s.stations.size() - 1)));
      if (j == 0 || j + 1 >= s.stations.size()) continue;
      EXPECT_TRUE(raised_fails(j)) << to_string(st.phase) << " " << to_string(st.binding) << " at s = " << at;
      ++tried;
    }
  }
  EXPECT_GE(tried, 6);
}

TEST(TimeOptimal, MaxAccelerationCapsTheRamp) {
  // with a gentle tangential acceleration limit the ramp is that constant acceleration: V^2 = 2 a s
  const CircleCase c;
  TimeOptimalLimits lim = c.limits(1000);
  lim.max_acceleration = 0.01;
  const TimeOptimalSchedule s = time_optimal_speed(c.placed(), c.rig.machine, c.rig.load, lim);
  const double s_probe = 0.05;
  const double v_hand = std::sqrt(2 * 0.01 * s_probe);
  EXPECT_LE(s.profile->speed_at(s_probe), v_hand);
  EXPECT_NEAR(s.profile->speed_at(s_probe), v_hand, 2e-4 * v_hand);  // the planner's margin under each limit
  EXPECT_EQ(s.stretches.front().binding, Binding::acceleration);
  for (const auto& x : s.check.series) ASSERT_LE(std::abs(x.st.a_t), 0.01 * (1 + 1e-9));
}

TEST(TimeOptimal, RefusesAMachineThatCannotHoldTheLoadAtRest) {
  CircleCase c;
  // a safety factor so high that the arm's friction alone exceeds 1/SF of the angular pull-out torque
  TimeOptimalLimits lim = c.limits(100);
  lim.safety_factor = 1e4;
  EXPECT_THROW(time_optimal_speed(c.placed(), c.rig.machine, c.rig.load, lim), InputError);
}

}  // namespace tu_machine_dynamics_test_time_optimal
