#pragma once
// All error metrics of a polar staircase against its tool path (docs/area-error.md):
//  - the exact area error (area_error.hpp);
//  - the deviation: the largest distance from the machine's quasi-static path to the tool path (deviation.hpp:
//    every node and the middle of every radial segment and arc, and the true maximum inside a piece where it can
//    lie there), and the bound of Eq. 4.1 (DeltaR where r <= DeltaR / DeltaTheta, r DeltaTheta beyond) at the
//    path's largest r;
//  - the thesis's F_sum, F_dif, F1 from the step counts of each segment (Eq. 4.5-4.6), each step counted in the
//    segment where the foot point of its middle lies, and from the chords (Eq. 4.15).
// Steps are recorded (one byte each) and measured by finish().
#include <cstdint>
#include <vector>

#include "cam/curve.hpp"
#include "metrics/area_error.hpp"
#include "metrics/f1.hpp"

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

class ErrorMeters final : public StepSink {
 public:
  // path: the tool-centre path in the machine frame, track: its polar track (both must outlive finish()).
  void reset(const Curve& path, const PolarTrack& track, const Grid& grid, int segments);
  void step(int axis, int dir, int64_t) override { record(axis, dir); }
  void record(int axis, int dir) {
    steps_.push_back(static_cast<uint8_t>(axis | (dir > 0 ? 2 : 0)));
    area_.record(axis, dir);
  }
  // Throws InputError when the staircase does not follow the path.
  ErrorMetrics finish(int64_t n0, int64_t m0);

 private:
  const Curve* path_ = nullptr;
  const PolarTrack* track_ = nullptr;
  Grid grid_;
  int segments_ = 1;
  std::vector<uint8_t> steps_;
  PolarAreaMeter area_;
};

}  // namespace polarcam
