#pragma once
// The tangential speed of a step stream, measured from its pulse rates: "the frequency of the command pulses is
// proportional to the velocity of the table in the corresponding direction" (000_4afce2e042f0d022.txt, Sec.
// 3.2.1). Between two consecutive pulses of one axis, that axis moves one step length in the time between them,
// so its speed over that interval is step_length / interval. The tangential speed at the middle of an interval of
// one axis is the hypotenuse of that axis's speed and the other axis's speed over its own interval containing the
// same instant. Every interval of every axis is one sample, weighted by its duration; the statistics are the
// smallest and largest sample and the duration-weighted mean and RMS deviation from a nominal speed.
//
// Over an interval where the axis turns round (the two pulses go opposite ways) it moves out and back by an
// unknown amount less than a step each way; its speed there is taken as step_length / interval, but no more than
// the faster of its neighbouring intervals (an axis decelerates into a reversal and accelerates out of it), so a
// path that just grazes a step level does not read as a burst of speed.
// Where the other axis has no interval containing the instant (before its first pulse or after its last), its
// speed is taken from its first (last) interval when the instant lies within one such interval of that pulse,
// and as zero otherwise. Two pulses of one axis with equal times count as one nanosecond apart.
// Details, the reasons and hand calculations: docs/cartesian.md.
#include <cstdint>
#include <vector>

#include "digitizer/digitize.hpp"  // StepSink

namespace polarcam {

struct PulseSpeedStats {
  uint64_t samples = 0;   // axis intervals measured
  double min_mps = 0.0, max_mps = 0.0;
  double mean_mps = 0.0;  // duration-weighted mean of the samples
  double rms_dev_mps = 0.0;  // duration-weighted RMS of (sample - nominal)
  double nominal_mps = 0.0;
};

class PulseSpeedMeter final : public StepSink {
 public:
  // Step lengths of axis 0 and axis 1, m (the BLU for a Cartesian machine).
  PulseSpeedMeter(double step0_m, double step1_m);
  void step(int axis, int dir, int64_t t_ns) override;
  // Statistics against the nominal tangential speed (m/s). All zero when no axis has two pulses.
  PulseSpeedStats stats(double nominal_mps) const;

 private:
  std::vector<double> interval_speeds(int axis) const;
  double len_[2];
  std::vector<int64_t> t_[2];
  std::vector<uint8_t> d_[2];  // 1 for a step in the + direction
};

}  // namespace polarcam
