#pragma once
// All error metrics of a polar staircase against its tool path (docs/area-error.md):
//  - the exact area error (area_error.hpp);
//  - the deviation: the largest distance from the machine's quasi-static path to the tool path (deviation.hpp:
//    every node and the middle of every radial segment and arc, and the true maximum inside a piece where it can
//    lie there), and the bound of Eq. 4.1 (DeltaR where r <= DeltaR / DeltaTheta, r DeltaTheta beyond) at the
//    path's largest r;
//  - the thesis's F_sum, F_dif, F1 from the step counts of each segment (Eq. 4.5-4.6), each step counted in the
//    segment where the foot point of its middle lies, and from the chords (Eq. 4.15).
// Steps are recorded (one byte each) and measured by finish(); or, after begin() with the start node, measured as
// they come in a window of constant size (area_error.hpp: the streamed mode; the deviation and the step counts
// are running values), with the same results. With set_parallel(true), the area meter runs on a second thread
// beside the deviation and the step counts (step_lane.hpp), with the same results again.
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "cam/curve.hpp"
#include "metrics/area_error.hpp"
#include "metrics/deviation.hpp"
#include "metrics/f1.hpp"
#include "metrics/step_lane.hpp"

namespace polarcam {

struct ErrorMetrics {
  AreaErrorResult area;
  double deviation_max_m = 0.0;
  Vec2 deviation_at;                 // the point of the machine path (machine frame, m) where it is largest
  double deviation_eq41_m = 0.0;     // Eq. 4.1 at the path's largest radius
  int segments = 0;
  F1Value f_counts;                  // Eq. 4.5-4.6 from the staircase's steps
  F1Value f_chords;                  // Eq. 4.15 on the same segments
};

// The segment of a parameter u of a path [u0, u1] cut into n equal segments: floor((u - u0) / (u1 - u0) n),
// clamped to 0 .. n - 1 (formula()). The formula is monotone in u, so a segment is the interval between the least
// parameters of it and of the next, found by bisection on the doubles the first time the segment is met. of()
// keeps the last segment's interval: a parameter within it (the usual case, a foot next to the last one) costs two
// comparisons instead of a division, and of(u) is formula(u) for every u.
class SegmentIndex {
 public:
  void reset(double u0, double u1, int segments);
  int formula(double u) const;
  int of(double u) {
    if (u >= lo_ && u < hi_) return seg_;
    return lookup(u);
  }

 private:
  int lookup(double u);
  double first(int i);  // the least double u with formula(u) >= i, 1 <= i < n
  double u0_ = 0.0, u1_ = 1.0;
  int n_ = 1;
  std::vector<double> first_;  // by segment; NaN where not found yet
  double lo_ = 0.0, hi_ = 0.0;  // the interval of segment seg_ (empty: none yet)
  int seg_ = 0;
};

class ErrorMeters final : public StepSink {
 public:
  // path: the tool-centre path in the machine frame, track: its polar track (both must outlive finish()).
  void reset(const Curve& path, const PolarTrack& track, const Grid& grid, int segments);
  // Run the area meter on a second thread (call after reset(), before stream_from() and the first step).
  void set_parallel(bool on) { parallel_ = on; }
  // Testing: the deviation finds every node's foot (DeviationMeter::set_bounds(false)); call before the first step.
  void set_deviation_bounds(bool on) { dev_bounds_ = on; }
  // Streams from here on: the staircase starts on node (n0, m0) (call after reset(), before the first step).
  // Not StepSink::begin, which the digitizer calls on every sink: the meters stream only when asked.
  void stream_from(int64_t n0, int64_t m0);
  void step(int axis, int dir, int64_t) override { record(axis, dir); }
  void record(int axis, int dir) {
    const auto s = static_cast<uint8_t>(axis | (dir > 0 ? 2 : 0));
    if (lane_) {  // the area meter on the lane's thread, the deviation here
      lane_->push(s);
      follow(axis, dir);
      return;
    }
    if (dev_)
      follow(axis, dir);
    else
      steps_.push_back(s);
    area_.record(axis, dir);
  }
  // Throws InputError when the staircase does not follow the path. After begin(): check streamed(); when it is
  // false the result is void and the steps must be replayed into meters without begin().
  ErrorMetrics finish(int64_t n0, int64_t m0);
  bool streamed() const { return area_.streamed(); }
  size_t peak_window() const { return area_.peak_window(); }

 private:
  void follow(int axis, int dir);  // the deviation and the step counts of one step
  void start_following(int64_t n0, int64_t m0);
  void follow_all(const uint8_t* steps, size_t count);
  void area_all(const uint8_t* steps, size_t count);
  // node (n, m) in the machine frame, the cosine and sine of the last angle remembered
  Vec2 node(double n, double m) {
    if (!(m == node_m_)) {  // a radial step keeps the angle: its two nodes share one cosine and sine
      node_m_ = m;
      turn(static_cast<int64_t>(m), node_cos_, node_sin_);
    }
    const double rho = n * grid_.dr;
    return Vec2{rho * node_cos_, rho * node_sin_};
  }
  double node_m_ = std::numeric_limits<double>::quiet_NaN(), node_cos_ = 0.0, node_sin_ = 0.0;
  // The cosine and sine of m DeltaTheta by the sum formulas, from those of the block of kTurnBlock angular steps
  // that holds m (computed when the block changes, its angle carried in two parts: exact but for the library's
  // cosine and sine) and a table of k DeltaTheta, k < kTurnBlock: within about one unit of rounding of the exact
  // node's, for four multiplications instead of a call. Where a turn is N whole steps the angle is the exact
  // 2 pi (m mod N) / N, not m times the rounded step.
  static constexpr int64_t kTurnBlock = 256;
  void turn(int64_t m, double& c, double& s);
  std::vector<double> tab_cos_, tab_sin_;  // 1 - cos and sin of k steps (made by reset())
  double step_hi_ = 0.0, step_lo_ = 0.0;
  int64_t block_ = std::numeric_limits<int64_t>::min();
  double block_cos_ = 1.0, block_sin_ = 0.0;
  double reach(double n) const;
  SegmentIndex segment_;  // a foot's segment of F1
  int segment_of(double u) { return segment_.of(u); }
  double foot_ = std::numeric_limits<double>::quiet_NaN();  // the last step's end's foot, and its segment
  int foot_seg_ = 0;
  std::unique_ptr<DeviationMeter> dev_;
  std::vector<long long> nr_, nt_;
  double n_ = 0, m_ = 0;

  const Curve* path_ = nullptr;
  const PolarTrack* track_ = nullptr;
  Grid grid_;
  int segments_ = 1;
  bool dev_bounds_ = true;
  std::vector<uint8_t> steps_;
  alignas(64) PolarAreaMeter area_;  // written by the lane's thread: on cache lines of its own
  alignas(64) bool parallel_ = false;
  std::unique_ptr<StepLane> lane_;  // streamed and parallel: the steps on their way to the area meter
};

}  // namespace polarcam
