#pragma once
// Step rates of a step stream, per axis, as a drive must deliver them (docs/compare.md):
//  - the largest sustained rate: 1 / the shortest interval between two consecutive steps of the axis that go
//    the same way;
//  - reversals: consecutive steps of the axis that go opposite ways (the path grazes or turns at a step level),
//    counted, with the shortest interval between such a pair. A reversal is not a rate the motor sustains: under
//    the nearest rule a path that just grazes a level steps out and back within microseconds.
// Streams in O(1) memory.
#include <cstdint>

#include "digitizer/digitize.hpp"  // StepSink

namespace polarcam {

struct AxisRates {
  uint64_t steps = 0;
  double max_rate_hz = 0.0;            // 0 when no two consecutive steps go the same way
  int64_t min_interval_ns = -1;        // of those same-direction pairs (-1: none)
  uint64_t reversals = 0;
  int64_t min_reversal_interval_ns = -1;
};

class StepRateMeter final : public StepSink {
 public:
  void step(int axis, int dir, int64_t t_ns) override {
    AxisRates& a = r_[axis & 1];
    Last& l = last_[axis & 1];
    if (a.steps > 0) {
      const int64_t iv = t_ns - l.t;
      int64_t& m = dir == l.dir ? a.min_interval_ns : a.min_reversal_interval_ns;
      if (m < 0 || iv < m) m = iv;
      if (dir != l.dir) ++a.reversals;
    }
    l.t = t_ns;
    l.dir = dir;
    ++a.steps;
  }
  // Rates with two steps of one axis in the same nanosecond counted as one nanosecond apart.
  AxisRates axis(int a) const {
    AxisRates r = r_[a & 1];
    if (r.min_interval_ns >= 0) r.max_rate_hz = 1e9 / static_cast<double>(r.min_interval_ns > 0 ? r.min_interval_ns : 1);
    return r;
  }

 private:
  struct Last {
    int64_t t = 0;
    int dir = 0;
  };
  AxisRates r_[2];
  Last last_[2];
};

}  // namespace polarcam
