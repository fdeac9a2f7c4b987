#include "process/band_control.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cam/error.hpp"
#include "process/ac_loop.hpp"
#include "process/checks.hpp"

namespace polarcam::process {
namespace {

void require(bool ok, const std::string& message, const std::string& key) {
  if (!ok) throw InputError(message, key);
}

}  // namespace

const char* band_quantity_name(BandQuantity q) {
  switch (q) {
    case BandQuantity::total_force: return "total_force";
    case BandQuantity::perpendicular_force: return "perpendicular_force";
    case BandQuantity::feed_per_tooth: return "feed_per_tooth";
  }
  return "total_force";
}

double feed_for_feed_per_tooth(double f_t, int teeth, double spindle_speed_rad_s) {
  return f_t * teeth * spindle_speed_rad_s / (2.0 * std::numbers::pi);
}

void apply_tool_limits(BandSettings& s, const ToolLimits& l) {
  for (Band& b : s.bands) {
    std::optional<double> lim;
    switch (b.quantity) {
      case BandQuantity::total_force: lim = l.shank_force_limit_N; break;
      case BandQuantity::perpendicular_force: lim = l.deflection_force_limit_N; break;
      case BandQuantity::feed_per_tooth: lim = l.feed_per_tooth_limit_m; break;
    }
    if (!lim) continue;
    if (b.upper > *lim)
      throw InputError("is above the tool's limit of " + std::to_string(*lim) + " (SI units): lower it below the limit",
                       "band." + b.event + ".upper");
    b.hard_limit = lim;
  }
}

void check(const BandSettings& s) {
  require(!s.bands.empty(), "give at least one [[band]]", "band");
  for (const Band& b : s.bands) {
    const std::string k = "band." + b.event;
    require(std::isfinite(b.lower) && b.lower >= 0.0, "must be 0 or more", k + ".lower");
    require(positive(b.upper) && b.upper > b.lower, "must be above the band's lower limit", k + ".upper");
    if (b.hard_limit) require(positive(*b.hard_limit), "must be positive", k + ".hard_limit");
  }
  require(positive(s.rate_hz) && s.rate_hz <= 1e4, "must be a rate above 0 and at most 10 kHz", "controller.rate");
  require(positive(s.step_fraction) && s.step_fraction <= 1.0, "must be a fraction above 0 and at most 1 (100 %)",
          "controller.step");
  require(positive(s.programmed_feed), "must be a positive speed", "controller.programmed_feed");
  require(positive(s.max_override) && s.max_override <= 10.0, "must be above 0 and at most 10 (1000 %)",
          "controller.max_override");
  require(std::isfinite(s.initial_override) && s.initial_override >= 0.0 && s.initial_override <= s.max_override,
          "must be from 0 to controller.max_override", "controller.initial_override");
  require(positive(s.drive_time_constant) && s.drive_time_constant < 100.0, "must be a positive time below 100 s",
          "plant.drive_time_constant");
  if (s.filter_cutoff_hz)
    require(positive(*s.filter_cutoff_hz) && *s.filter_cutoff_hz < s.sim_rate_hz / 4,
            "must be a positive frequency below a quarter of plant.rate", "plant.filter_cutoff");
  require(positive(s.sim_rate_hz) && s.sim_rate_hz <= 1e6, "must be a rate above 0 and at most 1 MHz", "plant.rate");
  const double ratio = s.sim_rate_hz / s.rate_hz;
  require(std::abs(ratio - std::round(ratio)) < 1e-6 && std::round(ratio) >= 1.0,
          "must be a whole multiple of controller.rate", "plant.rate");
  require(positive(s.duration_s) && s.duration_s * s.sim_rate_hz <= 5e6,
          "must be a positive time of at most 5 million plant steps", "simulation.duration");
  const BandCut& c = s.cut;
  require(c.teeth >= 1 && c.teeth <= 100, "must be 1 to 100", "cut.teeth");
  require(positive(c.spindle_speed_rad_s), "must be a positive spindle speed", "cut.spindle_speed");
  require(positive(c.specific_force), "must be a positive specific force (N/mm^3)", "cut.specific_force");
  require(positive(c.radial_depth) && c.radial_depth < 10.0, "must be a positive length below 10 m", "cut.radial_depth");
  require(positive(c.axial_depth) && c.axial_depth < 10.0, "must be a positive length below 10 m", "cut.axial_depth");
  if (c.step_time) {
    require(std::isfinite(*c.step_time) && *c.step_time > 0.0 && *c.step_time < s.duration_s,
            "must be a time within the simulation", "cut.step_time");
    require(positive(c.step_axial_depth) && c.step_axial_depth < 10.0, "must be a positive length below 10 m",
            "cut.step_axial_depth");
  }
  require(std::isfinite(c.perpendicular_ratio) && c.perpendicular_ratio >= 0.0 && c.perpendicular_ratio <= 1.0,
          "must be from 0 to 1", "cut.perpendicular_ratio");
}

BandResult simulate_band_control(const BandSettings& s) {
  check(s);
  const BandCut& c = s.cut;
  const double dt = 1.0 / s.sim_rate_hz;
  const long every = std::lround(s.sim_rate_hz / s.rate_hz);
  const long n_steps = std::lround(std::floor(s.duration_s * s.sim_rate_hz + 1e-9)) + 1;
  const double tau = 2.0 * std::numbers::pi / (c.teeth * c.spindle_speed_rad_s);
  const double drive_a = std::exp(-dt / s.drive_time_constant);
  // third-order Butterworth: w^3 / (s^3 + 2 w s^2 + 2 w^2 s + w^3), controllable canonical form
  std::optional<Discrete> filter;
  if (s.filter_cutoff_hz) {
    const double w = 2.0 * std::numbers::pi * *s.filter_cutoff_hz;
    filter = discretise_zoh({0, 1, 0, 0, 0, 1, -w * w * w, -2 * w * w, -2 * w}, {0, 0, w * w * w}, 3, 1, dt);
  }
  double z[3] = {0, 0, 0};

  BandResult r;
  const double step = s.step_fraction * s.programmed_feed;
  r.effective_gain = step * s.rate_hz;
  std::vector<double> feed(static_cast<size_t>(n_steps), 0.0);
  auto feed_at = [&](long k) {  // the table's speed tau ago, linearly between steps; 0 before the start
    const double tb = static_cast<double>(k) * dt - tau;
    if (tb <= 0.0) return 0.0;
    const double f = tb / dt;
    const long i = static_cast<long>(std::floor(f));
    const double w = f - static_cast<double>(i);
    const double a = feed[static_cast<size_t>(i)];
    const double b = i + 1 < k ? feed[static_cast<size_t>(i + 1)] : a;
    return a + w * (b - a);
  };
  std::vector<bool> exceeded(s.bands.size(), false);
  double v = 0.0, override_ = s.initial_override;
  for (long k = 0; k < n_steps; ++k) {
    const double t = static_cast<double>(k) * dt;
    feed[static_cast<size_t>(k)] = v;
    const double b = c.step_time && t >= *c.step_time ? c.step_axial_depth : c.axial_depth;
    const double F = c.specific_force * c.radial_depth * b * feed_at(k) * tau;
    const double F_perp = c.perpendicular_ratio * F;
    const double f_t = v * tau;
    r.peak_total_force = std::max(r.peak_total_force, F);
    r.peak_perpendicular_force = std::max(r.peak_perpendicular_force, F_perp);
    r.peak_feed_per_tooth = std::max(r.peak_feed_per_tooth, f_t);
    double sensed = F;
    if (filter) {
      const Discrete& d = *filter;
      double nz[3];
      for (int i = 0; i < 3; ++i)
        nz[i] = d.Ad[static_cast<size_t>(i * 3)] * z[0] + d.Ad[static_cast<size_t>(i * 3 + 1)] * z[1] +
                d.Ad[static_cast<size_t>(i * 3 + 2)] * z[2] + d.Bd[static_cast<size_t>(i)] * F;
      sensed = z[0];  // the output before this step's update: the filter's state at t
      std::copy(nz, nz + 3, z);
    }
    auto value = [&](const Band& bd, bool truth) {
      switch (bd.quantity) {
        case BandQuantity::total_force: return truth ? F : sensed;
        case BandQuantity::perpendicular_force: return c.perpendicular_ratio * (truth ? F : sensed);
        case BandQuantity::feed_per_tooth: return f_t;
      }
      return 0.0;
    };
    for (size_t i = 0; i < s.bands.size(); ++i)
      if (s.bands[i].hard_limit && value(s.bands[i], true) > *s.bands[i].hard_limit) exceeded[i] = true;

    if (k % every == 0) {
      BandSample smp;
      smp.t = t;
      smp.feed = v;
      smp.total_force = sensed;
      smp.perpendicular_force = c.perpendicular_ratio * sensed;
      smp.feed_per_tooth = f_t;
      int above = -1, inside = -1;
      for (size_t i = 0; i < s.bands.size(); ++i) {
        const double q = value(s.bands[i], false);
        if (q > s.bands[i].upper && above < 0) above = static_cast<int>(i);
        if (q >= s.bands[i].lower && q <= s.bands[i].upper && inside < 0) inside = static_cast<int>(i);
      }
      double next = override_;
      if (above >= 0) {
        smp.action = BandAction::decrease;
        smp.active_event = above;
        next -= s.step_fraction;
      } else if (inside >= 0) {
        smp.action = BandAction::hold;
        smp.active_event = inside;
      } else {
        smp.action = BandAction::increase;
        next += s.step_fraction;
      }
      if (next < -1e-12 || next > s.max_override + 1e-12) {
        ++r.override_limited_samples;
        next = std::clamp(next, 0.0, s.max_override);
      }
      override_ = next;
      smp.command = override_ * s.programmed_feed;
      r.series.push_back(smp);
    }
    // the feed drive: a first-order lag on the command, exact over the step
    v = drive_a * v + (1.0 - drive_a) * override_ * s.programmed_feed;
  }
  for (size_t i = 0; i < s.bands.size(); ++i)
    if (exceeded[i]) r.exceeded.push_back(s.bands[i].event);

  // the limit cycle over the last window
  r.window_s = std::min(2.0, 0.5 * s.duration_s);
  const double t_end = r.series.back().t;
  int last_dir = 0;
  bool first = true;
  for (const BandSample& smp : r.series) {
    if (smp.t < t_end - r.window_s - 1e-12) continue;
    if (first) {
      r.cycle_feed_min = r.cycle_feed_max = smp.command;
      first = false;
    }
    r.cycle_feed_min = std::min(r.cycle_feed_min, smp.command);
    r.cycle_feed_max = std::max(r.cycle_feed_max, smp.command);
    const int dir = smp.action == BandAction::increase ? 1 : smp.action == BandAction::decrease ? -1 : 0;
    if (dir == 0) continue;
    if (last_dir != 0 && dir != last_dir) ++r.reversals;
    last_dir = dir;
  }
  r.limit_cycle = r.reversals >= 4;

  // the feed it had settled at before the step (or the end): held for the last 0.5 s
  const double t_settle = c.step_time ? *c.step_time : t_end + 1.0;
  const BandSample* last = nullptr;
  bool steady = true;
  for (const BandSample& smp : r.series) {
    if (smp.t >= t_settle) break;
    last = &smp;
  }
  if (last) {
    for (const BandSample& smp : r.series) {
      if (smp.t > last->t) break;
      if (smp.t >= last->t - 0.5 && smp.action != BandAction::hold) steady = false;
    }
    if (steady && last->t >= 0.5) r.settled_feed_before_step = last->command;
  }
  return r;
}

}  // namespace polarcam::process
