#pragma once
// The event-band feed controller of B. K. Fussell and D. P. Gagne, "Self-Directed Control of End Milling"
// (WL-TR-91-4027, 1991), Sec. V-VI: each prevent event (shank failure: the total force; tooth failure: the feed
// per tooth; tool deflection: the force perpendicular to the feed) has a band [lower, upper]. Every controller
// period (100 Hz) the feed override is
//   decreased by one step when any event is above its upper limit,
//   held when none is above and any is inside its band,
//   increased by one step when no event is active (every quantity below its lower limit),
// a step being a fraction (1 %) of the programmed feed; the override stays within 0 and max_override (the
// machine's override potentiometer, 0-150 %). The effective gain is step x programmed feed x rate.
//
// The simulated cut (the document's Sec. IV model is not printed; this is the lumped model of Elbestawi 1980,
// Sec. 4.4, with the same delays): the feed drive a first-order lag, the total force F = k a b f_t(t - tau) with
// f_t = v / (z Omega / 2 pi) the feed per tooth a tooth period ago, the perpendicular force a fixed fraction of
// it, and the force sensors read through a third-order Butterworth low-pass (Sec. VI: 10 Hz). The axial depth
// may step during the cut (Table 1: 0.25 in to 0.5 in). SI units throughout.
#include <optional>
#include <string>
#include <vector>

#include "process/limits.hpp"

namespace polarcam::process {

enum class BandQuantity { total_force, perpendicular_force, feed_per_tooth };
const char* band_quantity_name(BandQuantity q);

struct Band {
  std::string event;      // "shank failure", ...
  BandQuantity quantity = BandQuantity::total_force;
  double lower = 0.0;     // N, or m for the feed per tooth
  double upper = 0.0;
  std::optional<double> hard_limit;  // the tool's limit (process/limits.hpp): exceeding it is reported
};

struct BandCut {
  int teeth = 4;
  double spindle_speed_rad_s = 2000.0 * 2.0 * 3.14159265358979323846 / 60.0;
  double specific_force = 0.0;      // k, N/m^3 (Eq. 4.17 of Elbestawi: F = k a b f_t)
  double radial_depth = 0.0;        // a, m
  double axial_depth = 0.0;         // b, m
  std::optional<double> step_time;  // s: the axial depth becomes step_axial_depth
  double step_axial_depth = 0.0;
  double perpendicular_ratio = 0.7; // F_perp / F
};

struct BandSettings {
  std::vector<Band> bands;
  double rate_hz = 100.0;
  double step_fraction = 0.01;      // of the programmed feed
  double programmed_feed = 0.0;     // m/s
  double initial_override = 0.0;    // fraction of the programmed feed at t = 0
  double max_override = 1.5;
  double drive_time_constant = 0.05;  // s
  std::optional<double> filter_cutoff_hz = 10.0;  // none: the sensors unfiltered
  double sim_rate_hz = 5000.0;      // the plant's integration rate (a whole multiple of rate_hz)
  double duration_s = 3.0;
  BandCut cut;
};

enum class BandAction { decrease, hold, increase };

struct BandSample {
  double t = 0.0;
  double feed = 0.0;            // m/s, the table's
  double total_force = 0.0;     // N, as sensed (filtered)
  double perpendicular_force = 0.0;
  double feed_per_tooth = 0.0;  // m, from the sensed feed
  double command = 0.0;         // m/s, the override times the programmed feed
  BandAction action = BandAction::hold;
  int active_event = -1;        // the highest-ranked (first listed) event above or inside its band, -1 none
};

struct BandResult {
  std::vector<BandSample> series;     // one per controller period
  double effective_gain = 0.0;        // (m/s)/s
  // a limit cycle: in the last `window` seconds (2 s, or half a shorter run) the action reversed (a decrease
  // after an increase or the reverse, holds between them ignored) at least four times
  bool limit_cycle = false;
  int reversals = 0;
  double window_s = 0.0;
  double cycle_feed_min = 0.0, cycle_feed_max = 0.0;   // the command over the window
  std::optional<double> settled_feed_before_step;  // the command at the step time (or the end), when it had held
                                                   // at least 0.5 s before
  double peak_total_force = 0.0;      // N, the true (unfiltered) force
  double peak_perpendicular_force = 0.0;
  double peak_feed_per_tooth = 0.0;
  std::vector<std::string> exceeded;  // events whose hard limit the true quantity exceeded
  int override_limited_samples = 0;   // periods at which the override was held at 0 or max_override
};

// InputError naming the setting (`controller.rate`, `band.NAME.upper`, ...) when it cannot describe a run.
void check(const BandSettings& s);
BandResult simulate_band_control(const BandSettings& s);

// The tool's limits as the bands' hard limits: the shank force limit (Fussell & Gagne Eq. 7) for total-force
// bands, the deflection force limit (Eq. 21) for perpendicular-force bands, the feed-per-tooth limit (Eq. 18) for
// feed-per-tooth bands, each when the tool's data give it. InputError naming `band.EVENT.upper` when a band's
// upper limit is above the tool's limit.
void apply_tool_limits(BandSettings& s, const ToolLimits& l);

// The feed (m/s) at which the feed per tooth is f_t: f_t z Omega / (2 pi) (Fussell & Gagne Eq. 19).
double feed_for_feed_per_tooth(double f_t, int teeth, double spindle_speed_rad_s);

}  // namespace polarcam::process
