#include "metrics/track_view.hpp"

#include "digitizer/polar_track.hpp"
#include "machine/cartesian/cartesian_track.hpp"

namespace polarcam::sweep {

TrackView view_of(const AxisTrack& track, Geometry geo) {
  const int ga = geo == Geometry::polar ? 1 : 0, ha = 1 - ga;  // the abscissa's and the height's track axis
  TrackView v;
  v.geo = geo;
  v.extrema = &track.extrema();
  v.closed = track.closed();
  v.winding = track.winding();
  v.g_min = track.q_min(ga).value;
  v.g_max = track.q_max(ga).value;
  v.pieces.reserve(track.pieces().size());
  for (const TrackPiece& p : track.pieces())
    v.pieces.push_back(PieceView{&p.Q[ga], &p.Q[ha], p.q_a[ga], p.q_b[ga], p.q_a[ha], p.q_b[ha], p.ext_begin, p.ext_end});
  return v;
}

TrackView view_of(const PolarTrack& track) { return view_of(track, Geometry::polar); }
TrackView view_of(const CartesianTrack& track) { return view_of(track, Geometry::cartesian); }

}  // namespace polarcam::sweep
