#include "process/constant_force.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "cam/error.hpp"

namespace polarcam::process {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// The largest V with V * unit <= limit (unit the quantity at 1 m/s), +inf when the quantity is zero.
double speed_for(double limit, double unit) { return unit > 0.0 ? limit / unit : kInf; }
}  // namespace

const char* to_string(FeedBinding b) {
  static constexpr const char* kNames[] = {"nominal_force", "breakage_force", "shank_force", "tooth_force",
                                           "deflection_force", "feed_per_tooth", "speed", "entry", "acceleration"};
  return kNames[static_cast<int>(b)];
}

const char* describe(FeedBinding b) {
  static constexpr const char* kWords[] = {"the nominal force",         "the breakage force",
                                           "the shank's force limit",   "one tooth's force limit",
                                           "the deflection limit",      "the feed-per-tooth limit",
                                           "the top feed",              "the planned entry",
                                           "the machine's acceleration"};
  return kWords[static_cast<int>(b)];
}

void check_constant_force_limits(const ConstantForceLimits& l) {
  auto positive = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError("must be positive and finite", what);
  };
  positive(l.nominal_force_N, "nominal_force");
  positive(l.max_speed, "speed");
  if (l.max_acceleration) positive(*l.max_acceleration, "max_acceleration");
  if (l.breakage_force_N) positive(*l.breakage_force_N, "breakage_force");
  if (l.shank_force_N) positive(*l.shank_force_N, "shank_force_limit");
  if (l.tooth_force_N) positive(*l.tooth_force_N, "tooth_force_limit");
  if (l.deflection_force_N) positive(*l.deflection_force_N, "deflection_force_limit");
  if (l.feed_per_tooth_m) positive(*l.feed_per_tooth_m, "feed_per_tooth_limit");
  if (l.entry_feed_per_tooth_m) positive(*l.entry_feed_per_tooth_m, "rapid_feed_per_tooth");
  if (!(l.entry_length_m >= 0.0) || !std::isfinite(l.entry_length_m))
    throw InputError("must be zero or a positive length", "entry_length");
  if (!(l.entry_fraction > 0.0) || !(l.entry_fraction <= 1.0)) throw InputError("must be in (0, 1]", "entry_fraction");
}

ConstantForceSchedule constant_force_schedule(const MillingPath& path, const ConstantForceLimits& lim) {
  check_constant_force_limits(lim);
  const auto& ms = path.stations();
  // the steady limit at each station, and what sets it
  struct Limit {
    double v;
    FeedBinding b;
  };
  auto steady = [&](size_t i) {
    const MillingForceAt u = path.at_station(i, 1.0);  // every quantity at 1 m/s
    Limit best{speed_for(lim.nominal_force_N, u.mean_resultant_N), FeedBinding::nominal_force};
    auto take = [&](double v, FeedBinding b) {
      if (v < best.v) best = {v, b};
    };
    if (lim.breakage_force_N) take(speed_for(*lim.breakage_force_N, u.peak_resultant_N), FeedBinding::breakage);
    if (lim.shank_force_N) take(speed_for(*lim.shank_force_N, u.peak_resultant_N), FeedBinding::shank);
    if (lim.tooth_force_N) take(speed_for(*lim.tooth_force_N, u.peak_tooth_N), FeedBinding::tooth);
    if (lim.deflection_force_N) take(speed_for(*lim.deflection_force_N, u.peak_normal_N), FeedBinding::deflection);
    if (lim.feed_per_tooth_m) take(path.speed_for_feed_per_tooth(*lim.feed_per_tooth_m), FeedBinding::feed_per_tooth);
    take(lim.max_speed, FeedBinding::speed);
    return best;
  };

  ConstantForceSchedule out;
  std::vector<Limit> limits;
  for (size_t i = 0; i < ms.size(); ++i) {
    const Limit l = steady(i);
    // a joint of two pieces: one station at that s, the lower of the two sides' limits
    if (!out.stations.empty() && ms[i].s <= out.stations.back().s) {
      if (l.v < limits.back().v) {
        limits.back() = l;
        out.stations.back().station = i;
      }
      continue;
    }
    out.stations.push_back({ms[i].s, 0.0, l.b, i});
    limits.push_back(l);
  }
  if (out.stations.size() < 2) throw InputError("the path is too short for a schedule", "path");

  // entering the cut: a third of the start's steady speed (at most the rapid feed per tooth's) for entry_length,
  // then V^2 linear in s up to the top speed over the next entry_length
  if (lim.entry_length_m > 0.0) {
    double ve = lim.entry_fraction * limits.front().v;
    if (lim.entry_feed_per_tooth_m) ve = std::min(ve, path.speed_for_feed_per_tooth(*lim.entry_feed_per_tooth_m));
    const double L = lim.entry_length_m, vt = lim.max_speed;
    for (size_t k = 0; k < out.stations.size(); ++k) {
      const double s = out.stations[k].s;
      if (s >= 2.0 * L) break;
      const double cap = s <= L ? ve : std::sqrt(ve * ve + (s - L) / L * (vt * vt - ve * ve));
      if (cap < limits[k].v) limits[k] = {cap, FeedBinding::entry};
    }
  }
  for (size_t k = 0; k < out.stations.size(); ++k) {
    out.stations[k].v = limits[k].v;
    out.stations[k].binding = limits[k].b;
  }
  // the largest acceleration: forward, then backward
  if (lim.max_acceleration) {
    const double a = *lim.max_acceleration;
    auto& st = out.stations;
    for (size_t k = 1; k < st.size(); ++k) {
      const double vmax = std::sqrt(st[k - 1].v * st[k - 1].v + 2.0 * a * (st[k].s - st[k - 1].s));
      if (vmax < st[k].v) st[k] = {st[k].s, vmax, FeedBinding::acceleration, st[k].station};
    }
    for (size_t k = st.size() - 1; k-- > 0;) {
      const double vmax = std::sqrt(st[k + 1].v * st[k + 1].v + 2.0 * a * (st[k + 1].s - st[k].s));
      if (vmax < st[k].v) st[k] = {st[k].s, vmax, FeedBinding::acceleration, st[k].station};
    }
  }
  // the path's exact ends
  out.stations.front().s = 0.0;
  for (size_t k = 0; k + 1 < out.stations.size(); ++k) {
    const FeedStation &p = out.stations[k], &q = out.stations[k + 1];
    out.total_time_s += 2.0 * (q.s - p.s) / (p.v + q.v);
    if (out.stretches.empty() || out.stretches.back().binding != p.binding)
      out.stretches.push_back({p.s, q.s, p.binding});
    else
      out.stretches.back().s1 = q.s;
  }
  return out;
}

}  // namespace polarcam::process
