#include "machine/cartesian/cartesian_track.hpp"

#include "digitizer/track_builder.hpp"

namespace polarcam {

CartesianTrack CartesianTrack::build(const Curve& path) {
  CartesianTrack tr;
  build_axis_track(path, CartesianMap{}, tr);
  return tr;
}

}  // namespace polarcam
