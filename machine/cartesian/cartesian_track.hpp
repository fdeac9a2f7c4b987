#pragma once
// The Cartesian track: a path's x(u), y(u) and arc length s(u) as adaptive piecewise Chebyshev series accurate
// to a few units in the last place, with the interior extrema of x and y, so that between consecutive extrema
// both coordinates are monotone. The Cartesian counterpart of the polar track (digitizer/polar_track.hpp), built
// from the same Chebyshev machinery (digitizer/chebyshev.hpp); the exact Cartesian step generator reads the path
// through it. Each piece [u_a, u_b] carries on t in [-1, 1]:
//   X(t) = x - x_a,  Y(t) = y - y_a,  V(t) = ds/dt,  S(t) = s - s_a (the integral of V).
#include <cstdint>
#include <vector>

#include "cam/curve.hpp"
#include "digitizer/chebyshev.hpp"

namespace polarcam {

struct XYPiece {
  double ua = 0, ub = 0;          // path parameter at the ends
  double s0 = 0, len = 0;         // arc length from the path start to ua; arc length of the piece
  double x_a = 0, x_b = 0;        // x at the ends (evaluated exactly, shared with the neighbours)
  double y_a = 0, y_b = 0;        // y at the ends
  Cheb X, Y, V, S;                // series on t in [-1, 1]
  uint32_t ext_begin = 0, ext_end = 0;  // [begin, end) into CartesianTrack::extrema(): sorted t in (-1, 1)
};

class CartesianTrack {
 public:
  // Builds the track of `path` (coordinates in metres). Throws InputError when the path is not finite or
  // cannot be resolved.
  static CartesianTrack build(const Curve& path);

  const std::vector<XYPiece>& pieces() const { return pieces_; }
  const std::vector<double>& extrema() const { return extrema_; }
  double length() const { return length_; }
  bool closed() const { return closed_; }

  double x(size_t piece, double t) const { return pieces_[piece].x_a + pieces_[piece].X(t); }
  double y(size_t piece, double t) const { return pieces_[piece].y_a + pieces_[piece].Y(t); }
  double s(size_t piece, double t) const { return pieces_[piece].s0 + pieces_[piece].S(t); }
  // Largest |x| and |y| on the path (for range checks).
  double max_abs_coordinate() const { return max_abs_; }
  // The path's bounding box (its ends and the extrema of x and y).
  struct Bounds {
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  };
  Bounds bounds() const { return bounds_; }

 private:
  std::vector<XYPiece> pieces_;
  std::vector<double> extrema_;
  double length_ = 0;
  double max_abs_ = 0;
  Bounds bounds_;
  bool closed_ = false;
};

}  // namespace polarcam
