#include "digitizer/polar_track.hpp"

#include "digitizer/track_builder.hpp"

namespace polarcam {

PolarTrack PolarTrack::build(const Curve& path) {
  PolarTrack tr;
  build_axis_track(path, PolarMap{path.rounding_scale()}, tr);
  return tr;
}

}  // namespace polarcam
