#pragma once
// Process signals recorded on a machine (docs/monitoring.md): a CSV file whose header names `time_s` first and
// then the signal columns, e.g.
//   time_s,force_N
//   time_s,current_A,speed_rad_per_s
// one row per sample, evenly spaced in time. Column names are letters, digits and '_' (the unit last, as in
// force_N); '#' lines and blank lines are skipped. Every fault is an InputError naming FILE:LINE and the column.
#include <string>
#include <vector>

namespace polarcam::process {

struct SignalRecord {
  double start_s = 0.0;   // time of the first sample
  double period_s = 0.0;  // the sample period, from the whole record
  std::vector<std::string> names;              // the signal columns, in the file's order (time_s excluded)
  std::vector<std::vector<double>> columns;    // one per name, all of the same length (>= 2)

  size_t samples() const { return columns.empty() ? 0 : columns.front().size(); }
  // The column `name`; nullptr when the file has none.
  const std::vector<double>* find(const std::string& name) const;
};

// At most this many samples (rows) in one file.
inline constexpr size_t kMaxSignalSamples = 20'000'000;

SignalRecord parse_signal_csv(const std::string& text, const std::string& file);
SignalRecord read_signal_csv(const std::string& path);

// The record as CSV text (`digits` significant digits, the time to the nanosecond): what parse_signal_csv reads.
std::string format_signal_csv(const SignalRecord& r, int digits = 7);

}  // namespace polarcam::process
