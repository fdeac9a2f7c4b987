#pragma once
// The bounding box of the nodes a step stream visits: the size of what the machine draws (to within the bulge of
// a polar arc between two nodes, r DeltaTheta^2 / 8, nanometres on the thesis's machine). Polar nodes (n, m) stand
// at n DeltaR (cos m DeltaTheta, sin m DeltaTheta) about the machine pole, Cartesian nodes (i, j) at
// (i BLU, j BLU). Streams in O(1) memory.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "cam/vec2.hpp"
#include "digitizer/digitize.hpp"  // StepSink

namespace polarcam {

class NodeBox final : public StepSink {
 public:
  // polar: res0 = DeltaR, res1 = DeltaTheta; Cartesian: res0 = res1 = BLU.
  NodeBox(bool polar, double res0, double res1, int64_t n0, int64_t n1) : polar_(polar), res_{res0, res1}, node_{n0, n1} {
    see();
  }
  void step(int axis, int dir, int64_t) override {
    node_[axis & 1] += dir;
    see();
  }
  Vec2 lo() const { return lo_; }
  Vec2 hi() const { return hi_; }
  Vec2 size() const { return hi_ - lo_; }

 private:
  void see() {
    Vec2 p;
    if (polar_) {
      const double r = static_cast<double>(node_[0]) * res_[0], a = static_cast<double>(node_[1]) * res_[1];
      p = {r * std::cos(a), r * std::sin(a)};
    } else {
      p = {static_cast<double>(node_[0]) * res_[0], static_cast<double>(node_[1]) * res_[1]};
    }
    if (first_) lo_ = hi_ = p, first_ = false;
    lo_ = {std::min(lo_.x, p.x), std::min(lo_.y, p.y)};
    hi_ = {std::max(hi_.x, p.x), std::max(hi_.y, p.y)};
  }
  bool polar_;
  double res_[2];
  int64_t node_[2];
  bool first_ = true;
  Vec2 lo_, hi_;
};

}  // namespace polarcam
