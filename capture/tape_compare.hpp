#pragma once
// Two step tapes compared as tapes (docs/capture.md, "Comparing with a tape"): the tape a controller was given
// (expected) and the tape decoded from what it did (seen, e.g. a step/dir recording of its pins through
// capture/capture.hpp). Step i of the one is matched with step i of the other: every step must be there, in
// order, on the same axis, in the same direction, and at the expected time divided by the speed scale P/Q (the
// scale the tape was played at) within a tolerance.
//
// Two steps of different axes at one seen time (on one controller tick, with tick_ns) may come in either order:
// when the seen pair matches the next two expected steps the other way round, they are taken as matched (counted
// in `simultaneous_swapped`). A controller ticking at a period T puts each step on a tick: with tick_ns = T, a seen
// time is first taken to the nearest multiple of T from the origin (the tick it fired on; the edge's distance
// from it, the interrupt's latency, is reported as max_jitter_ns), and the error is measured from that tick.
// Times are compared exactly (integers: the expected tape's ticks, the seen nanoseconds).
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "digitizer/digitize.hpp"

namespace polarcam {

class TapeReader;

struct TapeCompareOptions {
  int64_t speed_num = 1, speed_den = 1;  // the expected times are divided by num/den (play's --speed-scale)
  int64_t tick_ns = 0;                   // > 0: seen times are taken to the nearest multiple of this first
  int64_t tolerance_ns = 0;              // the largest time error accepted
  size_t max_listed = 20;                // mismatches kept in the list (all counted)
};

struct TapeMismatch {
  enum Kind { order = 0, time = 1, missing = 2, extra = 3 };
  Kind kind = order;
  uint64_t index = 0;                          // the step's place in the tape, from 1
  int expected_axis = 0, expected_dir = 0;     // (missing, order, time)
  int seen_axis = 0, seen_dir = 0;             // (extra, order, time)
  double expected_ns = 0;                      // the expected time, scaled
  int64_t seen_ns = 0;                         // as seen (before taking it to its tick)
  double error_ns = 0;                         // time: |seen (on its tick) - expected|
};
const char* to_string(TapeMismatch::Kind k);

struct TapeComparison {
  uint64_t steps_expected = 0, steps_seen = 0;
  uint64_t matched = 0;              // in order, axis and direction, and within the tolerance
  uint64_t order_mismatches = 0;     // another axis or direction at that place
  uint64_t time_mismatches = 0;      // the right step, beyond the tolerance
  uint64_t simultaneous_swapped = 0; // pairs of one seen tick matched the other way round
  double max_time_error_ns = 0;      // over the steps in order (seen time on its tick, when tick_ns)
  uint64_t worst_step = 0;           // its place, from 1 (0: none)
  double max_raw_error_ns = 0;       // the same, from the seen time itself
  double max_jitter_ns = 0;          // the seen times' distance from their ticks (tick_ns only)
  std::vector<TapeMismatch> listed;  // the first max_listed mismatches of any kind
  uint64_t mismatches() const {
    return order_mismatches + time_mismatches + (steps_expected > steps_seen ? steps_expected - steps_seen : 0) +
           (steps_seen > steps_expected ? steps_seen - steps_expected : 0);
  }
  bool ok() const { return mismatches() == 0; }
};

// The expected tape read as the seen steps arrive (a StepSink: give it to the capture's decoder, or feed it a
// tape). InputError naming the expected tape when it is not a polar or Cartesian step tape it can read, or for
// bad options.
class TapeComparer final : public StepSink {
 public:
  TapeComparer(const std::string& expected_tape, const TapeCompareOptions& o);
  ~TapeComparer() override;
  TapeComparer(const TapeComparer&) = delete;
  TapeComparer& operator=(const TapeComparer&) = delete;

  // The expected tape's header fields a seen tape needs (grid, home, start node).
  const TapeReader& expected() const { return *reader_; }

  void step(int axis, int dir, int64_t t_ns) override;
  // The rest of the expected tape counted as missing; the result.
  TapeComparison finish();

 private:
  struct Seen {
    int axis, dir;
    int64_t t_ns;
  };
  struct Expected {
    int axis, dir;
    uint64_t t_ticks;
  };
  bool fill(size_t n);  // at least n expected steps ahead, unless the tape ends
  int64_t on_tick(int64_t t_ns) const;  // the seen time's tick (tick_ns), else the time itself
  void match(const Seen& s);
  void list(const TapeMismatch& m);
  TapeCompareOptions o_;
  std::unique_ptr<TapeReader> reader_;
  uint64_t tick_ps_ = 1000, cum_ = 0;
  std::deque<Expected> ahead_;
  bool have_held_ = false, finished_ = false;
  Seen held_{};
  TapeComparison r_;
};

// The seen tape against the expected one (both files).
TapeComparison compare_tapes(const std::string& expected_tape, const std::string& seen_tape,
                             const TapeCompareOptions& o);

}  // namespace polarcam
