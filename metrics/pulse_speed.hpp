#pragma once
// The tangential speed of a step stream, measured from its pulse rates: "the frequency of the command pulses is
// proportional to the velocity of the table in the corresponding direction" (M. A. Elbestawi's thesis, McMaster
// University, 1980, Sec. 3.2.1). Between two consecutive pulses of one axis, that axis moves one step length in the time between them,
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
//
// The measurement streams: it pulls each axis's pulses in order with a lookahead of two, so a tape of any length
// is measured in constant memory (it is read four times).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "digitizer/digitize.hpp"  // StepSink

namespace polarcam {

struct PulseSpeedStats {
  uint64_t samples = 0;      // axis intervals measured
  double min_mps = 0.0, max_mps = 0.0;
  double mean_mps = 0.0;     // duration-weighted mean of the samples
  double rms_dev_mps = 0.0;  // duration-weighted RMS of (sample - nominal)
  double nominal_mps = 0.0;
};

// The samples binned in time, for plotting the speed along the path: each bin keeps the smallest and the largest
// sample whose interval's middle falls in it and their duration-weighted mean (NaN where a bin holds none).
struct SpeedTrace {
  SpeedTrace(int bins, double t_end_s);
  void add(double t_s, double v, double w);
  int bins() const { return static_cast<int>(vmin.size()); }
  double t_end_s = 0.0;
  std::vector<double> vmin, vmax, sw, swv;
  double mean(int i) const;
};

struct Pulse {
  int64_t t_ns = 0;
  int dir = 1;
  double length_m = 0.0;  // distance the tool moves for this step
};

// One axis's pulses in time order.
class PulseSource {
 public:
  virtual ~PulseSource() = default;
  virtual bool next(Pulse& p) = 0;
};

// Statistics of the pulses of axes 0 and 1. `make(axis)` returns a std::unique_ptr<PulseSource> over a fresh
// pass of that axis's pulses; each axis is read twice. All zero when no axis has two pulses.
template <class MakeSource>
PulseSpeedStats measure_pulse_speed(MakeSource make, double nominal_mps, SpeedTrace* trace = nullptr);

// Statistics of a step tape (either kind): on a Cartesian tape a step is one resolution of its axis; on a polar
// tape a radial step is DeltaR and an angular step r DeltaTheta with r = n DeltaR at the step. `speed_scale` K
// plays the tape with every time divided by K (the player's speed scaling, Sec. 3.6). Throws InputError for an
// unreadable or damaged tape.
PulseSpeedStats measure_tape_speed(const std::string& tape_path, double nominal_mps, double speed_scale = 1.0,
                                   SpeedTrace* trace = nullptr);

// In memory: records a stream (as a StepSink) with fixed step lengths per axis and measures it. For tests and
// short streams; memory grows with the stream (use measure_tape_speed for tapes).
class PulseSpeedMeter final : public StepSink {
 public:
  PulseSpeedMeter(double step0_m, double step1_m);
  void step(int axis, int dir, int64_t t_ns) override;
  PulseSpeedStats stats(double nominal_mps) const;

 private:
  double len_[2];
  std::vector<Pulse> p_[2];
};

// ------------------------------------------------------------------------------------------- implementation

namespace pulse_speed_detail {

struct Interval {
  int64_t t0 = 0, t1 = 0;
  double v = 0.0;  // m/s, turnarounds capped
};

// The intervals of one axis in order, each with its capped speed (which needs the pulses around it).
class Intervals {
 public:
  explicit Intervals(PulseSource& s);
  bool next(Interval& iv);

 private:
  bool read(Pulse& p) { return s_.next(p); }
  PulseSource& s_;
  Pulse prev_, a_, b_, c_;  // the pulse before the current interval, its two ends, the pulse after it
  bool has_prev_ = false, has_a_ = false, has_b_ = false, has_c_ = false;
};

// Adds the samples of `a` (with the other axis `b`) to the sums.
struct Sums {
  double sw = 0, swv = 0, swd = 0, vmin = 0, vmax = 0;
  uint64_t n = 0;
};
void add_samples(PulseSource& a, PulseSource& b, double nominal, Sums& sums, SpeedTrace* trace);
PulseSpeedStats finish(const Sums& s, double nominal);

}  // namespace pulse_speed_detail

template <class MakeSource>
PulseSpeedStats measure_pulse_speed(MakeSource make, double nominal_mps, SpeedTrace* trace) {
  pulse_speed_detail::Sums sums;
  for (int a = 0; a < 2; ++a) {
    auto sa = make(a);
    auto sb = make(1 - a);
    pulse_speed_detail::add_samples(*sa, *sb, nominal_mps, sums, trace);
  }
  return pulse_speed_detail::finish(sums, nominal_mps);
}

}  // namespace polarcam
