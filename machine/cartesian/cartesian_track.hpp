#pragma once
// The Cartesian track: a path's x(u), y(u) and arc length s(u): the axis track (digitizer/axis_track.hpp) of the
// Cartesian axis map q0 = x, q1 = y (metres). The exact Cartesian step generator and the Cartesian error meters
// read the path through it.
#include <algorithm>
#include <cmath>
#include <limits>

#include "cam/curve.hpp"
#include "digitizer/axis_track.hpp"

namespace polarcam {

// The Cartesian axis map (digitizer/track_builder.hpp): the point's own coordinates; no singularity.
struct CartesianMap {
  static constexpr double kEps = std::numeric_limits<double>::epsilon();
  static constexpr const char* kFrame = "";
  static constexpr const char* kSingular = "is singular";  // never: every point maps
  static constexpr const char* kRough = "it is not smooth";

  bool coords(Vec2 p, const double[2], double q[2], double& aux) const {
    q[0] = p.x;
    q[1] = p.y;
    aux = 0.0;
    return true;
  }
  bool smooth(const double[2], const double[2]) const { return true; }
  // The scale of a coordinate is the size of the point on the piece, both coordinates: a path computed in polar
  // form (a theta-rho pattern, a rotated drawing) rounds y at the size of x where it crosses the x axis.
  void tolerances(const double qa[2], const double span[2], double, double tol[2]) const {
    const double size = std::abs(qa[0]) + std::abs(qa[1]) + span[0] + span[1];
    tol[0] = 16 * kEps * size + 1e-300;
    tol[1] = 16 * kEps * size + 1e-300;
  }
  int close(const double first[2], double last[2]) const {  // a closed path ends exactly where it starts
    last[0] = first[0];
    last[1] = first[1];
    return 0;
  }
};

class CartesianTrack : public AxisTrack {
 public:
  // Builds the track of `path` (coordinates in metres). Throws InputError when the path is not finite or
  // cannot be resolved.
  static CartesianTrack build(const Curve& path);

  double x(size_t piece, double t) const { return q(0, piece, t); }
  double y(size_t piece, double t) const { return q(1, piece, t); }
  // The path's bounding box (its ends and the extrema of x and y).
  struct Bounds {
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  };
  Bounds bounds() const { return {q_min(0).value, q_max(0).value, q_min(1).value, q_max(1).value}; }
  // Largest |x| and |y| on the path (for range checks).
  double max_abs_coordinate() const {
    const Bounds b = bounds();
    return std::max({std::abs(b.x0), std::abs(b.x1), std::abs(b.y0), std::abs(b.y1)});
  }
};

}  // namespace polarcam
