#pragma once
// The track of a path in the coordinates of a machine's two axes: q0(u), q1(u) and the arc length s(u) as
// adaptive piecewise Chebyshev series accurate to a few units in the last place, whatever the kinematics. An
// axis map (track_builder.hpp, docs/kinematics.md) says how a path point becomes the two axis coordinates:
//   polar:            q0 = r, q1 = theta (unwrapped) about the machine pole;
//   Cartesian:        q0 = x, q1 = y;
//   theta-rho:        q0 = r + c theta (the radial motor of a coupled arm), q1 = theta.
// Each piece [u_a, u_b] carries on t in [-1, 1]:
//   Q[a](t) = q_a - q_a(u_a),  dQ[a] = dQ[a]/dt,  V(t) = ds/dt,  S(t) = s - s_a (the integral of V),
// plus the interior extrema of both coordinates (roots of dQ[0] and dQ[1]), so that between consecutive extrema
// both coordinates are monotone. The step walker (step_walker.hpp), the error metrics and the dynamics all read
// the path through it.
#include <cstdint>
#include <utility>
#include <vector>

#include "digitizer/chebyshev.hpp"

namespace polarcam {

struct TrackPiece {
  double ua = 0, ub = 0;         // path parameter at the ends
  double s0 = 0, len = 0;        // arc length from the path start to ua; arc length of the piece
  double q_a[2] = {0, 0};        // axis coordinates at ua (evaluated exactly, shared with the previous piece)
  double q_b[2] = {0, 0};        // axis coordinates at ub
  Cheb Q[2], dQ[2], V, S;        // series on t in [-1, 1] (derivatives with respect to t)
  uint32_t ext_begin = 0, ext_end = 0;  // [begin, end) into AxisTrack::extrema(): sorted t in (-1, 1)
  uint32_t turn_begin = 0, turn_end = 0;  // [begin, end) into AxisTrack::turns(): those of axis 1 alone

  double u_at(double t) const { return 0.5 * (ua + ub) + 0.5 * (ub - ua) * t; }
};

struct TrackExtent {
  double value;
  size_t piece;
  double t;
};

class AxisTrack {
 public:
  const std::vector<TrackPiece>& pieces() const { return pieces_; }
  const std::vector<double>& extrema() const { return extrema_; }
  // The extrema of axis 1 alone (where it turns: a polar track's arm reverses), sorted t in (-1, 1) a piece, at
  // least 1e-14 apart and from the ends (TrackPiece::turn_begin, turn_end).
  const std::vector<double>& turns() const { return turns_; }
  double length() const { return length_; }
  bool closed() const { return closed_; }
  // Turns a closed path makes about the axis map's centre (its angular axis); 0 for open paths and for maps
  // without an angle.
  int winding() const { return winding_; }

  // Axis coordinate a (0 or 1) and arc length at (piece, t).
  double q(int a, size_t piece, double t) const { return pieces_[piece].q_a[a] + pieces_[piece].Q[a](t); }
  double s(size_t piece, double t) const { return pieces_[piece].s0 + pieces_[piece].S(t); }
  // Range of axis coordinate a over the path, with where it is reached.
  TrackExtent q_min(int a) const { return qmin_[a]; }
  TrackExtent q_max(int a) const { return qmax_[a]; }

  // Piece and t at arc length s (clamped to the path).
  std::pair<size_t, double> locate(double s) const;

 protected:
  template <class Map>
  friend class TrackBuilder;
  friend struct PolylineTrackFill;  // theta-rho polylines (theta_rho.cpp)
  // Arc lengths, extrema and ranges of the pieces once they are fitted.
  void finish();

  std::vector<TrackPiece> pieces_;
  std::vector<double> extrema_, turns_;
  double length_ = 0;
  bool closed_ = false;
  int winding_ = 0;
  TrackExtent qmin_[2]{}, qmax_[2]{};
};

// Roots of a series in (-1, 1) where it changes sign (sampling plus a search at dips), appended in order.
void cheb_sign_changes(const Cheb& d, std::vector<double>& out);

}  // namespace polarcam
