#pragma once
// Tangential speed along the path as a function of arc length s, and the time t(s) = integral ds / V(s) at which
// the tool reaches s. The digitizer times each step by t(s_step). Profiles:
//  - constant: V from the first step, as the thesis (t = s / V);
//  - trapezoid: from rest to V at acceleration a, cruise, and back to rest at the end (triangle when the path
//    is too short to reach V);
//  - table: V given at arc-length stations, linear in s between them, held constant beyond the ends
//    (t is integrated exactly: ds / (V0 + k s) gives a logarithm);
//  - squared table: V^2 given at stations, linear in s between them (constant tangential acceleration
//    a = (V1^2 - V0^2) / (2 h) on each interval, the natural output of a phase-plane speed planner); a station may be
//    at rest, t over an interval is exactly 2 h / (V0 + V1).
#include <memory>
#include <vector>

namespace polarcam {

// The longest path duration a tape can time: 2^62 ns (about 146 years). The factories below refuse a profile
// whose total time exceeds it, naming the lowest speed that fits.
inline constexpr double kMaxDurationNs = 4611686018427387904.0;

class SpeedProfile {
 public:
  virtual ~SpeedProfile() = default;
  virtual double time_at(double s) const = 0;   // s
  virtual double speed_at(double s) const = 0;  // m/s
  // Tangential acceleration dV/dt = V dV/ds at s (m/s^2); one-sided (from above) where it jumps.
  virtual double accel_at(double s) const = 0;
  // Arc lengths strictly inside (0, length) where the acceleration jumps (ramp ends, table stations), sorted.
  virtual std::vector<double> kinks() const { return {}; }
  // A lower bound on the speed over the arc lengths [sa, sb] (m/s); 0 where none is known. The digitizer turns it
  // into how far an arc length may be off for a time to stay within a given fraction of a nanosecond.
  virtual double min_speed(double sa, double sb) const {
    (void)sa;
    (void)sb;
    return 0.0;
  }
  double length() const { return length_; }     // m, the path length the profile was made for
  double total_time() const { return time_at(length_); }

 protected:
  explicit SpeedProfile(double length) : length_(length) {}

 private:
  double length_;
};

using SpeedProfilePtr = std::shared_ptr<const SpeedProfile>;

SpeedProfilePtr make_constant_speed(double v, double length);
SpeedProfilePtr make_trapezoid_speed(double v, double accel, double length);
struct SpeedStation {
  double s, v;
};
SpeedProfilePtr make_table_speed(std::vector<SpeedStation> stations, double length);
// Stations (s, V) from s = 0 to s = length, s increasing, V >= 0 and never two neighbours both at rest; V^2 linear in s
// between them. Throws InputError naming the first offending station.
SpeedProfilePtr make_table_speed_sq(std::vector<SpeedStation> stations, double length);

}  // namespace polarcam
