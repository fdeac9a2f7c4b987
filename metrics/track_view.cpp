#include "metrics/track_view.hpp"

#include <algorithm>

#include "digitizer/polar_track.hpp"
#include "machine/cartesian/cartesian_track.hpp"

namespace polarcam::sweep {

TrackView view_of(const PolarTrack& track) {
  TrackView v;
  v.geo = Geometry::polar;
  v.extrema = &track.extrema();
  v.closed = track.closed();
  v.winding = track.winding();
  v.g_min = track.theta_min().value;
  v.g_max = track.theta_max().value;
  v.pieces.reserve(track.pieces().size());
  for (const TrackPiece& p : track.pieces())
    v.pieces.push_back(PieceView{&p.Th, &p.R, p.th_a, p.th_b, p.r_a, p.r_b, p.ext_begin, p.ext_end});
  return v;
}

TrackView view_of(const CartesianTrack& track) {
  TrackView v;
  v.geo = Geometry::cartesian;
  v.extrema = &track.extrema();
  v.closed = track.closed();
  v.winding = 0;
  v.pieces.reserve(track.pieces().size());
  bool first = true;
  auto see = [&](double x) {
    if (first) v.g_min = v.g_max = x, first = false;
    v.g_min = std::min(v.g_min, x);
    v.g_max = std::max(v.g_max, x);
  };
  const auto& E = track.extrema();
  for (const XYPiece& p : track.pieces()) {
    v.pieces.push_back(PieceView{&p.X, &p.Y, p.x_a, p.x_b, p.y_a, p.y_b, p.ext_begin, p.ext_end});
    see(p.x_a);
    see(p.x_b);
    for (uint32_t k = p.ext_begin; k < p.ext_end; ++k) see(p.x_a + p.X(E[k]));
  }
  return v;
}

}  // namespace polarcam::sweep
