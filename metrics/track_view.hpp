#pragma once
// A path's track as the area sweep sees it (sector_sweep.hpp): pieces with an abscissa g(t) and a height h(t),
// Chebyshev series on t in [-1, 1], both monotone between consecutive extrema. The polar track gives g = theta about
// the machine pole and h = r (digitizer/polar_track.hpp); the Cartesian track gives g = x and h = y
// (machine/cartesian/cartesian_track.hpp); both are axis tracks (digitizer/axis_track.hpp) read through one
// function. The views point into the track, which must outlive them.
#include <cstdint>
#include <vector>

#include "digitizer/chebyshev.hpp"

namespace polarcam {
class AxisTrack;
class PolarTrack;
class CartesianTrack;
}  // namespace polarcam

namespace polarcam::sweep {

enum class Geometry : uint8_t { polar, cartesian };

// One piece: g(t) = g_a + G(t), h(t) = h_a + H(t). Polar: g = theta (unwrapped, rad), h = r (m). Cartesian: g = x,
// h = y (m).
struct PieceView {
  const Cheb* G = nullptr;
  const Cheb* H = nullptr;
  double g_a = 0, g_b = 0, h_a = 0, h_b = 0;
  uint32_t ext_begin = 0, ext_end = 0;  // [begin, end) into TrackView::extrema
};

struct TrackView {
  Geometry geo = Geometry::polar;
  std::vector<PieceView> pieces;
  const std::vector<double>* extrema = nullptr;
  bool closed = false;
  int winding = 0;              // turns of a closed path about the pole (polar; 0 for Cartesian)
  double g_min = 0, g_max = 0;  // the path's range of abscissa
};

// The view of an axis track: polar, abscissa theta = axis 1, height r = axis 0; Cartesian, abscissa x = axis 0,
// height y = axis 1.
TrackView view_of(const AxisTrack& track, Geometry geo);
TrackView view_of(const PolarTrack& track);
TrackView view_of(const CartesianTrack& track);

}  // namespace polarcam::sweep
