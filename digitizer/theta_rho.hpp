#pragma once
// The theta-rho coupled arm (sand tables): an arm turned by the angular motor about the pole, carrying a radial
// carriage driven by the radial motor through a mechanism geared to the arm, so that turning the arm alone moves
// the ball radially. The motors' positions are
//   theta (rad, the angular motor, as on the polar machine),
//   q = r + c theta (m, the radial motor),
// with c the coupling in metres per radian (the gear ratio; 0: the plain polar machine, negative when turning
// the arm draws the ball inward). The digitizer steps q on DeltaR = grid.dr and theta on DeltaTheta with the
// polar machine's rules; tape axis 0 is the radial motor, axis 1 the angular motor. The work area's r_min /
// r_max bound the ball's radius r (the radial motor is geared to the arm: its position q grows with every turn of
// a pattern whose theta accumulates, and has no travel of its own to bound). A closed path that winds about the pole does not bring the radial
// motor back to its start (it ends 2 pi c per turn away), so such a tape is not periodic.
#include "cam/theta_rho_path.hpp"
#include "digitizer/digitize.hpp"
#include "digitizer/polar_track.hpp"

namespace polarcam {

// The theta-rho axis map (track_builder.hpp): the polar map with q = r + c theta in place of r.
struct ThetaRhoMap {
  static constexpr const char* kFrame = PolarMap::kFrame;
  static constexpr const char* kSingular = PolarMap::kSingular;
  static constexpr const char* kRough = PolarMap::kRough;

  PolarMap polar;
  double c = 0.0;  // m/rad

  bool coords(Vec2 p, const double ref[2], double q[2], double& aux) const {
    const bool ok = polar.coords(p, ref, q, aux);
    q[0] += c * q[1];
    return ok;
  }
  bool smooth(const double a[2], const double b[2]) const { return polar.smooth(a, b); }
  // q carries the rounding of r and that of c theta
  void tolerances(const double qa[2], const double span[2], double aux_min, double tol[2]) const {
    polar.tolerances(qa, span, aux_min, tol);
    tol[0] += std::abs(c) * tol[1];
  }
  // Same r and theta advanced by whole turns: q advanced by 2 pi c a turn.
  int close(const double first[2], double last[2]) const {
    const int turns = polar.close(first, last);
    last[0] = first[0] + c * (PolarMap::kTwoPi * turns);
    return turns;
  }
};

class ThetaRhoTrack : public AxisTrack {
 public:
  // Builds the track of `path` (origin at the pole) for coupling c (m/rad). Throws InputError as PolarTrack.
  static ThetaRhoTrack build(const Curve& path, double c);
  // Builds the track of a theta-rho polyline from its vertices (polyline_track below).
  static ThetaRhoTrack build(const ThetaRhoPath& path, double c, double r_floor);
  double coupling() const { return c_; }
  double q_radial(size_t piece, double t) const { return q(0, piece, t); }
  double theta(size_t piece, double t) const { return q(1, piece, t); }

 private:
  double c_ = 0.0;
};

// The track of a theta-rho polyline (cam/theta_rho_path.hpp) taken from its vertices, not from x and y, so that
// it is exact through the pole: on each segment q0 = rho + c theta and q1 = theta are linear (degree-1 series,
// no interior extrema), as the tables move. The arc length that times the steps is that of the ball with rho
// replaced by sqrt(rho^2 + r_floor^2): r_floor = 0 gives the ball's own path; r_floor = V / omega_max keeps the
// arm's angular speed at or below omega_max where the ball passes near the centre at speed V (a turn of the arm
// at the centre moves the ball nowhere). Throws InputError naming the segment whose timing length is zero
// (the arm turns at the centre with r_floor = 0).
PolarTrack polyline_polar_track(const ThetaRhoPath& path, double r_floor);

// Every step of both motors along the track (as digitize() for the polar machine).
DigitizeResult digitize(const ThetaRhoTrack& track, const Grid& grid, StepRule rule, const SpeedProfile& profile,
                        StepSink* sink);

}  // namespace polarcam
