#pragma once
// The exact Cartesian step-time generator: the modern counterpart of the DDA, and the Cartesian twin of the
// polar digitizer's `nearest` rule (digitizer/digitize.hpp). In BLU units f = x / BLU (axis x) and f = y / BLU
// (axis y), each axis is a quantiser with threshold 1/2: from node v it steps up when f reaches v + 1/2 and down
// when f falls below v - 1/2, so the tool always stands on the grid node nearest the path point. A step's time
// is t(s) of the speed profile at the arc length s where the path meets the step's level, rounded to the nearest
// nanosecond from the start (no drift). When both axes step at the same point, x comes first. It is the one step
// walker (digitizer/step_walker.hpp) on the Cartesian track.
#include "digitizer/speed_profile.hpp"
#include "machine/cartesian/cartesian.hpp"
#include "machine/cartesian/cartesian_track.hpp"

namespace polarcam {

// Steps the track on a grid of `blu` metres. `sink` may be null (counting and timing only).
CartesianResult step_exact(const CartesianTrack& track, double blu, const SpeedProfile& profile, StepSink* sink);

}  // namespace polarcam
