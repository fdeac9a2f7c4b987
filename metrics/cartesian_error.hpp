#pragma once
// The error metrics of a Cartesian staircase against its tool path, with the same definitions as the polar ones
// (docs/area-error.md, docs/compare.md):
//  - the exact area error: the integral of |winding number| of the cycle tool path -> connector -> staircase
//    backwards -> connector, where the staircase is the machine's quasi-static path, the axis-aligned unit segments
//    through the nodes (i BLU, j BLU) the tape visits. Computed by the polar meter's machinery (StairAreaMeter) on
//    strips of x one BLU wide: the staircase's x steps are its level strands (y = j BLU), its y steps have no
//    extent in x, and the path is read through its Cartesian track (machine/cartesian/cartesian_track.hpp);
//  - the deviation: the largest distance from the staircase to the tool path (deviation.hpp).
// Both expect the tool path in the Cartesian machine's frame (the contour's own frame). Steps are recorded (the
// area meter keeps about 140 bytes per x step, the deviation one byte per step) and measured by finish().
#include <cstdint>
#include <vector>

#include "cam/curve.hpp"
#include "machine/cartesian/cartesian.hpp"
#include "machine/cartesian/cartesian_track.hpp"
#include "metrics/area_error.hpp"

namespace polarcam {

// The Cartesian meter: rises are y steps, runs x steps, "sectors" strips of x one BLU wide.
using CartesianAreaResult = StairAreaResult;

class CartesianAreaMeter final : public StairStepMeter {
 public:
  CartesianAreaMeter() : StairStepMeter(kAxisY) {}
  // Binds the meter to the path's Cartesian track (which must outlive finish()) on a grid of `blu` metres;
  // forgets recorded steps.
  void reset(const CartesianTrack& track, double blu);
  // The staircase starts on node (i0, j0). Throws InputError when it does not follow the path.
  CartesianAreaResult finish(int64_t i0, int64_t j0);
};

struct CartesianErrorMetrics {
  CartesianAreaResult area;
  double deviation_max_m = 0.0;
  Vec2 deviation_at;  // the point of the staircase (m, Cartesian frame) where it is largest
};

class CartesianErrorMeters final : public StepSink {
 public:
  // path: the tool-centre path in the Cartesian frame, track: its Cartesian track (both must outlive finish()).
  void reset(const Curve& path, const CartesianTrack& track, double blu);
  void step(int axis, int dir, int64_t) override { record(axis, dir); }
  void record(int axis, int dir) {
    steps_.push_back(static_cast<uint8_t>((axis & 1) | (dir > 0 ? 2 : 0)));
    area_.record(axis, dir);
  }
  // Throws InputError when the staircase does not follow the path.
  CartesianErrorMetrics finish(int64_t i0, int64_t j0);

 private:
  const Curve* path_ = nullptr;
  double blu_ = 0.0;
  std::vector<uint8_t> steps_;
  CartesianAreaMeter area_;
};

}  // namespace polarcam
