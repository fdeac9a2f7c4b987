#include "metrics/cartesian_error.hpp"

#include <cmath>
#include <stdexcept>

#include "cam/error.hpp"
#include "metrics/deviation.hpp"

namespace polarcam {

void CartesianAreaMeter::reset(const CartesianTrack& track, double blu) {
  if (!(blu > 0.0) || !std::isfinite(blu)) throw InputError("the Cartesian resolution must be a length above zero");
  core_.reset(sweep::view_of(track), StairGrid{sweep::Geometry::cartesian, blu, blu, 0});
}

CartesianAreaResult CartesianAreaMeter::finish(int64_t i0, int64_t j0) {
  return core_.finish(j0, i0);  // the core's nodes are (height, abscissa)
}

void CartesianErrorMeters::reset(const Curve& path, const CartesianTrack& track, double blu) {
  path_ = &path;
  blu_ = blu;
  steps_.clear();
  area_.reset(track, blu);
}

CartesianErrorMetrics CartesianErrorMeters::finish(int64_t i0, int64_t j0) {
  if (!path_) throw std::logic_error("CartesianErrorMeters::finish before reset");
  CartesianErrorMetrics out;
  out.area = area_.finish(i0, j0);  // checks that the staircase follows the path
  const double blu = blu_, reach = 3.0 * blu + 1e-12;
  int64_t node[2] = {i0, j0};
  DeviationMeter dev(*path_);
  dev.start(cartesian_position(node, blu), reach);
  for (uint8_t s : steps_) {
    const int axis = s & 1, dir = (s & 2) ? 1 : -1;
    StairPiece piece;
    piece.a = cartesian_position(node, blu);
    node[axis] += dir;
    piece.b = cartesian_position(node, blu);
    dev.piece(piece, reach);
  }
  out.deviation_max_m = dev.max();
  out.deviation_at = dev.at();
  steps_.clear();
  return out;
}

}  // namespace polarcam
