#pragma once
// A synthetic milling force for tests and examples (docs/monitoring.md): Z teeth at n rev/s, each tooth in cut
// over `engagement` of a revolution with a half-sine force pulse K h sin(pi s) of its chip h (s from 0 at entry to
// 1 at exit; peak_force_N = K times one feed per tooth); the chip is
// what the tooth removes beyond the surface left by the teeth before it, so a tooth's radial run-out
// r_j = runout cos(2 pi j / Z) gives h = f_z + r_j - r_{j-1} and a broken tooth (after break_at_s) cuts nothing
// and leaves its chip to the next one (two feeds per tooth). Optional chatter: a sine of chatter_force at
// chatter_frequency_hz from chatter_at_s, growing linearly over 0.1 s. Gaussian noise of noise_force (Box-Muller
// on std::mt19937_64, whose sequence the C++ standard fixes: the same seed gives the same signal everywhere).
#include <cstdint>
#include <optional>

#include "process/signal_file.hpp"

namespace polarcam::process {

struct MillingSignalOptions {
  double duration_s = 6.0;
  double sample_rate_hz = 500.0;
  double spindle_rev_per_s = 10.0;
  int teeth = 4;
  double engagement = 0.25;      // fraction of a revolution each tooth cuts (0.25: a quarter, half immersion)
  double peak_force_N = 500.0;   // K f_z: the peak force of a tooth cutting one feed per tooth
  double runout = 0.1;           // r_j amplitude as a fraction of the feed per tooth
  double noise_N = 10.0;         // standard deviation of the added noise
  uint64_t seed = 1;
  std::optional<double> break_at_s;
  int broken_tooth = 0;          // 0 .. teeth-1: the tooth that breaks
  std::optional<double> chatter_at_s;
  double chatter_frequency_hz = 0.0;
  double chatter_force_N = 0.0;  // amplitude of the chatter sine
};

// The signal as a record with one column, force_N. InputError naming the option when one is out of range.
SignalRecord milling_force_signal(const MillingSignalOptions& o);

// The start time of pass `k` (k = m Z + j: revolution m, tooth j) of the generator: k / (Z n).
double milling_pass_start(const MillingSignalOptions& o, long k);

}  // namespace polarcam::process
