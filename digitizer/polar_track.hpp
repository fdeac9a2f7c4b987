#pragma once
// The polar track: the tool-centre path as the machine sees it, r(u) and the unwrapped theta(u) about the machine
// pole, with arc length s(u), as adaptive piecewise Chebyshev series accurate to a few units in the last place.
// Each piece [u_a, u_b] carries on t in [-1, 1]:
//   R(t) = r - r_a,  Th(t) = theta - theta_a,  V(t) = ds/dt,  S(t) = s - s_a (the integral of V),
// plus the interior extrema of r and theta (roots of R' and Th'), so that between consecutive extrema both
// coordinates are monotone. The digitizer, the error metrics and the dynamics all read the path through it.
#include <cstdint>
#include <vector>

#include "cam/curve.hpp"
#include "digitizer/chebyshev.hpp"

namespace polarcam {

struct TrackPiece {
  double ua = 0, ub = 0;        // path parameter at the ends
  double s0 = 0, len = 0;       // arc length from the path start to ua; arc length of the piece
  double r_a = 0, r_b = 0;      // r at the ends (evaluated exactly, shared with the neighbours)
  double th_a = 0, th_b = 0;    // unwrapped theta at the ends
  Cheb R, dR, Th, dTh, V, S;    // series on t in [-1, 1] (derivatives with respect to t)
  uint32_t ext_begin = 0, ext_end = 0;  // [begin, end) into PolarTrack::extrema(): sorted t in (-1, 1)

  double u_at(double t) const { return 0.5 * (ua + ub) + 0.5 * (ub - ua) * t; }
};

struct TrackExtent {
  double value;
  size_t piece;
  double t;
};

class PolarTrack {
 public:
  // Builds the track of `path`, whose origin is the machine pole. Throws InputError when the path is not finite,
  // passes through the pole, or cannot be resolved.
  static PolarTrack build(const Curve& path);

  const std::vector<TrackPiece>& pieces() const { return pieces_; }
  const std::vector<double>& extrema() const { return extrema_; }
  double length() const { return length_; }
  bool closed() const { return closed_; }
  // Number of turns a closed path makes about the pole (theta_end - theta_start) / 2 pi; 0 for open paths.
  int winding() const { return winding_; }

  TrackExtent r_min() const { return rmin_; }
  TrackExtent r_max() const { return rmax_; }
  TrackExtent theta_min() const { return thmin_; }
  TrackExtent theta_max() const { return thmax_; }

  // r, theta and s at (piece, t)
  double r(size_t piece, double t) const { return pieces_[piece].r_a + pieces_[piece].R(t); }
  double theta(size_t piece, double t) const { return pieces_[piece].th_a + pieces_[piece].Th(t); }
  double s(size_t piece, double t) const { return pieces_[piece].s0 + pieces_[piece].S(t); }

  // Piece and t at arc length s (clamped to the path).
  std::pair<size_t, double> locate(double s) const;

 private:
  std::vector<TrackPiece> pieces_;
  std::vector<double> extrema_;
  double length_ = 0;
  bool closed_ = false;
  int winding_ = 0;
  TrackExtent rmin_{}, rmax_{}, thmin_{}, thmax_{};
};

// Roots of a series in (-1, 1) where it changes sign (sampling plus a search at dips), appended in order.
void cheb_sign_changes(const Cheb& d, std::vector<double>& out);

}  // namespace polarcam
