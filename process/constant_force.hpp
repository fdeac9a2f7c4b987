#pragma once
// The constant-force feed schedule of a milled contour (docs/process.md, "The constant-force schedule"): the
// fastest feed V(s) along the path at which the mean cutting force is the nominal force and no process limit is
// exceeded: the breakage force (M. A. Elbestawi, A Study of an Adaptive Control Constraint System for Milling,
// 1980, Eq. 5.33) and the shank limit (B. K. Fussell & D. P. Gagne, Self-Directed Control of End Milling, 1991,
// Eq. 7) on the peak resultant force, the tooth limit (Eq. 13) on the peak force of one tooth, the deflection
// limit (Eq. 21) on the peak force perpendicular to the feed, the feed-per-tooth limit (Eq. 18) and the machine's
// top speed. Elbestawi's controller holds the force at F_nom by feedback (Eq. 5.19); the forces of
// process/milling_path.hpp are proportional to the feed, so the same force is reached ahead of time: each limit
// Q_max on a quantity Q(s, V) = V q(s) gives V <= Q_max / q(s).
//
// Entering the cut: Elbestawi's strategy B (Sec. 5.8) stops the feed when the cutter meets the work and resumes
// with the NC loop at a third of its gain until the force has settled (140 ms). Planned ahead, the schedule enters
// at a third of the speed the steady limits allow at the start (and at most the speed of Elbestawi's rapid feed
// per tooth, Eq. 5.35, whose first force peak on entering a wall reaches the breakage force) for `entry_length`,
// then raises V^2 linearly in s over the next `entry_length` to the machine's top speed (where the steady limits do
// not bind first). With a largest acceleration the schedule is then lowered by a forward and a backward pass
// (V_{i+1}^2 <= V_i^2 + 2 a h and back), as the time-optimal schedule does.
#include <optional>
#include <vector>

#include "process/milling_path.hpp"

namespace polarcam::process {

struct ConstantForceLimits {
  double nominal_force_N = 0.0;                // the mean resultant force to hold
  double max_speed = 0.0;                      // m/s, the machine's (the job's) top feed
  std::optional<double> max_acceleration;      // m/s^2
  std::optional<double> breakage_force_N;      // on the peak resultant force
  std::optional<double> shank_force_N;         // on the peak resultant force
  std::optional<double> tooth_force_N;         // on the peak force of one tooth
  std::optional<double> deflection_force_N;    // on the peak force perpendicular to the feed
  std::optional<double> feed_per_tooth_m;      // on the centre's feed per tooth
  std::optional<double> entry_feed_per_tooth_m;  // the rapid feed per tooth, a cap while entering
  double entry_length_m = 0.0;                 // 0: no planned entry
  double entry_fraction = 1.0 / 3.0;           // of the steady speed at the start
  bool operator==(const ConstantForceLimits&) const = default;
};

// Throws InputError naming the field.
void check_constant_force_limits(const ConstantForceLimits& l);

// What sets the speed at a point.
enum class FeedBinding { nominal_force, breakage, shank, tooth, deflection, feed_per_tooth, speed, entry, acceleration };
const char* to_string(FeedBinding b);
// The same in words, for people: "the nominal force", "the deflection limit", ...
const char* describe(FeedBinding b);

struct FeedStation {
  double s = 0.0;      // m
  double v = 0.0;      // m/s, the schedule
  FeedBinding binding = FeedBinding::nominal_force;
  size_t station = 0;  // the MillingPath station it stands for (at a joint: the side with the lower limit)
};

struct FeedStretch {
  double s0 = 0.0, s1 = 0.0;  // m
  FeedBinding binding = FeedBinding::nominal_force;
};

struct ConstantForceSchedule {
  std::vector<FeedStation> stations;   // s strictly increasing from 0 to the path's length; V^2 linear between
  std::vector<FeedStretch> stretches;  // consecutive intervals with the same binding (that of the interval's start)
  double total_time_s = 0.0;           // sum of 2 h / (V_i + V_{i+1})
};

ConstantForceSchedule constant_force_schedule(const MillingPath& path, const ConstantForceLimits& lim);

}  // namespace polarcam::process
