#pragma once
// The Cartesian machine that polarcam compares the polar machine with: two linear axes x and y with the same
// basic length unit (BLU) each, node (i, j) at x = i BLU, y = j BLU in the contour's own frame (origin at the
// contour pole O1; the polar placement does not apply). Its step streams go to the same StepSink and the same
// tape format as the polar digitizer's (TapeAxes::cartesian, axis 0 = x, axis 1 = y), so every consumer of a
// tape reads them. Two generators make them:
//  - step_exact (cartesian_exact.hpp): every step at the exact time the tool centre, moving along the path at the
//    speed profile's tangential speed, crosses x = (i + 1/2) BLU or y = (j + 1/2) BLU (the polar digitizer's
//    `nearest` rule on a square grid);
//  - run_dda (dda.hpp): a conventional NC control's linear and circular DDAs, clocked by a feed accumulator at a
//    fixed interrupt rate, interpolating the path's approximation by lines and arcs.
// Its quasi-static path is the staircase of axis-aligned unit segments through the nodes the tape visits.
#include <algorithm>
#include <cstdint>

#include "cam/vec2.hpp"
#include "digitizer/digitize.hpp"  // StepSink, AxisSummary

namespace polarcam {

enum : int { kAxisX = 0, kAxisY = 1 };

// Node nearest a point (rounding half up, as the nearest rule: floor(f + 1/2)). Throws InputError when the
// point is too far from the origin for the resolution (more than 2^50 BLU).
int64_t cartesian_node(double coordinate_m, double blu);
// Throws InputError when a path of `length_m` would take more than 10^10 steps on a grid of `blu` (a tape of tens
// of gigabytes: the resolution is too fine for the path).
void check_step_budget(double length_m, double blu);
// Position of a node, m.
inline Vec2 cartesian_position(const int64_t node[2], double blu) {
  return {static_cast<double>(node[0]) * blu, static_cast<double>(node[1]) * blu};
}

struct CartesianResult {
  int64_t start[2] = {0, 0}, end[2] = {0, 0};  // nodes before the first and after the last step
  AxisSummary axis[2];          // x, y: counts; min_interval_ns; max_rate_hz = 1e9 / min_interval_ns
  double path_length_m = 0.0;   // of the path the generator followed (the lines and arcs for the DDA)
  double duration_s = 0.0;      // start to end of the motion
  int64_t duration_ns = 0;
  int64_t last_step_ns = 0;
  bool closed = false;
  bool returns_to_start = false;  // the tape ends on its start node
  uint64_t steps() const { return axis[0].steps() + axis[1].steps(); }
};

// Counts steps per axis and their shortest intervals into a CartesianResult (used by both generators).
class CartesianTally {
 public:
  explicit CartesianTally(CartesianResult& r, StepSink* sink) : r_(r), sink_(sink) {}
  void step(int axis, int dir, int64_t t_ns) {
    AxisSummary& a = r_.axis[axis];
    if (a.steps() > 0) {
      int64_t iv = t_ns - last_[axis];
      if (a.min_interval_ns < 0 || iv < a.min_interval_ns) a.min_interval_ns = iv;
    }
    last_[axis] = t_ns;
    (dir > 0 ? a.plus : a.minus) += 1;
    node_[axis] += dir;
    r_.last_step_ns = t_ns;
    if (sink_) sink_->step(axis, dir, t_ns);
  }
  void start_at(const int64_t n[2]) {
    node_[0] = r_.start[0] = n[0];
    node_[1] = r_.start[1] = n[1];
  }
  // Fills the end node, the step rates and the closure flag (duration_ns must be set).
  void finish() {
    r_.end[0] = node_[0];
    r_.end[1] = node_[1];
    // two steps of one axis within the same nanosecond count as one tick apart
    for (auto& a : r_.axis)
      a.max_rate_hz = a.min_interval_ns >= 0 ? 1e9 / static_cast<double>(std::max<int64_t>(a.min_interval_ns, 1)) : 0.0;
    if (r_.duration_ns < r_.last_step_ns) r_.duration_ns = r_.last_step_ns;
    r_.returns_to_start = r_.end[0] == r_.start[0] && r_.end[1] == r_.start[1];
  }
  const int64_t* node() const { return node_; }

 private:
  CartesianResult& r_;
  StepSink* sink_;
  int64_t last_[2] = {0, 0};
  int64_t node_[2] = {0, 0};
};

}  // namespace polarcam
