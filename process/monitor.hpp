#pragma once
// Process monitoring from one sampled signal (a cutting force or a feed motor's current; docs/monitoring.md):
//  - tool breakage from the tooth-period averages: the normalised first difference
//    D'(t) = (F_av(t) - F_av(t-1)) / F_av(t-1) of J. Peng, "Design and Analysis of a CNC System for Machining and
//    Monitoring" (MASc thesis, UBC, 1989), Sec. 3.5, Eq. 3.68-3.69, against a run-out threshold, and the first and
//    second differences of B. K. Fussell and D. P. Gagne, "Self-Directed Control of End Milling" (WL-TR-91-4027,
//    1991), Events and Associated Detection Methods 1, Eq. 1-3 (after Altintas, Yellowley and Tlusty);
//  - chatter by Fussell and Gagne's rule (Events 5, Eq. 22-24): the force oscillation amplitude above a set
//    point and the largest peak of the power spectral density (Welch) away from the tooth frequency and the
//    spindle's harmonics, above the density at the tooth frequency;
//  - overload: a tooth-period average above a limit.
#include <optional>
#include <string>
#include <vector>

#include "process/signal_file.hpp"

namespace polarcam::process {

// The signal a monitor watches, taken from a signal file.
struct MonitorSignal {
  std::string name;        // the column, or "estimated_force_N"
  std::string quantity;    // "force", "current" or "" (a column of another unit)
  double start_s = 0.0, sample_rate_hz = 0.0;
  std::vector<double> x;
};
// The column `column` of `r` (empty: force_N if the file has it, else current_A, else the first column). With
// `estimate_force`, the feeding force estimated from the columns current_A and speed_rad_per_s by Peng's Eq. 3.40
// (process/force_estimator.hpp: Appendix A's drive with the friction `friction_N_m_s` and the file's sample
// period), one sample shorter. InputError naming the file or the option when a column is missing.
MonitorSignal select_signal(const SignalRecord& r, const std::string& file, const std::string& column,
                            bool estimate_force, double friction_N_m_s = 0.196);

// The average of the signal over each tooth period: the samples are taken as constant over their sample period
// (sample k covers [k, k+1) sample periods), and tooth period i, P = f_s / (n Z) samples long (f_s the sample
// rate, n the spindle speed in rev/s, Z the teeth), covers [i P, (i+1) P) with the samples it cuts weighted by
// their overlap, so P need not be a whole number. Only whole tooth periods within the record are returned.
struct ToothPeriod {
  double start_s = 0.0, end_s = 0.0;  // relative to the first sample
  double mean = 0.0;
};
// InputError when the rate, speed or teeth are not positive, or a tooth period is shorter than two samples.
std::vector<ToothPeriod> tooth_period_averages(const std::vector<double>& x, double sample_rate_hz,
                                               double spindle_rev_per_s, int teeth);

// Per tooth period t >= 1: first difference D1 = F(t) - F(t-1) (Eq. 3.68, Fussell Eq. 1), second difference
// D2 = D1(t) - D1(t-1) (Fussell Eq. 2; 0 at t = 1), normalised D' = D1 / F(t-1) (Eq. 3.69, Fussell Eq. 3),
// its denominator not less than `floor` (a tooth that cut nothing would divide by zero).
struct Differences {
  std::vector<double> d1, d2, normalised;  // index t - 1 for tooth period t
};
Differences tooth_differences(const std::vector<ToothPeriod>& p, double floor);

enum class BreakageRule {
  peng,     // |D'| above the threshold (Peng, Sec. 3.5)
  fussell,  // |D'| above the threshold and |D2| > |D1| (Fussell and Gagne: the second difference confirms)
};

struct MonitorOptions {
  double sample_rate_hz = 0.0;
  double spindle_rev_per_s = 0.0;
  int teeth = 0;
  // Breakage. The first `learn_revolutions` revolutions are taken as a clean cut (no event is reported in
  // them): the default threshold is threshold_factor times the largest |D'| there (run-out and noise), and not
  // less than min_threshold. `threshold` set overrides it.
  double learn_revolutions = 3.0;
  double threshold_factor = 3.0;
  double min_threshold = 0.1;
  std::optional<double> threshold;
  BreakageRule rule = BreakageRule::peng;
  // Chatter: Welch PSD over consecutive blocks of 4 Hann segments with half overlap; a segment is the power of
  // two of samples at least segment_spindle_periods / n long (its bins at most n / 8 apart). A peak within
  // harmonic_bins bins of a multiple of the spindle frequency (the tooth frequency's harmonics among them) is
  // not chatter. The amplitude F_R is sqrt(2) times the block's standard deviation; its set point defaults to
  // amplitude_factor times the first block's, or `chatter_setpoint`.
  bool chatter = true;
  double segment_spindle_periods = 8.0;
  double harmonic_bins = 2.0;
  double amplitude_factor = 1.2;
  std::optional<double> chatter_setpoint;
  // Overload: a tooth-period average above this (the signal's unit).
  std::optional<double> overload;
};

enum class EventKind { breakage, chatter, overload };
const char* to_string(EventKind k);

// One event: consecutive tooth periods (or chatter blocks) that exceed, merged until a whole revolution (a
// block) passes without one. time_s: the end of the first tooth period (block) that exceeded; value there.
struct MonitorEvent {
  EventKind kind = EventKind::breakage;
  double time_s = 0.0, end_s = 0.0;
  double value = 0.0, threshold = 0.0;
  int count = 1;                     // tooth periods or blocks in the event
  double frequency_hz = 0.0;         // chatter: the PSD peak's frequency
};

struct MonitorResult {
  double tooth_frequency_hz = 0.0, samples_per_tooth = 0.0;
  size_t tooth_periods = 0;
  double breakage_threshold = 0.0;   // the threshold used on |D'|
  double learned_max_normalised = 0.0;  // the largest |D'| of the learning revolutions
  double learn_end_s = 0.0;
  double chatter_setpoint = 0.0;     // 0 when the record is shorter than two chatter blocks
  double chatter_block_s = 0.0;
  size_t chatter_blocks = 0;
  std::vector<MonitorEvent> events;  // in time order
};

// InputError (naming the option) when the options are out of range or the record holds fewer than
// learn_revolutions + 1 revolutions.
MonitorResult monitor_signal(const std::vector<double>& x, const MonitorOptions& o);

// The one-sided power spectral density by Welch's method (Hann window, half overlap, density scaling: units^2/Hz)
// of x sampled at rate fs with segments of `segment` samples (a power of two, <= x.size()); bin k is at
// k fs / segment Hz. Deterministic (Eigen's FFT).
std::vector<double> welch_psd(const std::vector<double>& x, double fs, size_t segment);

}  // namespace polarcam::process
