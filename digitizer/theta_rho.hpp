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
#include <type_traits>

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
// replaced by max(rho, r_floor): r_floor = 0 gives the ball's own path; r_floor = V / omega_max keeps the arm's
// angular speed at or below omega_max where the ball passes within r_floor of the centre at speed V (a turn of
// the arm at the centre moves the ball nowhere), and leaves the ball's speed V everywhere else. Segments are
// split where rho crosses r_floor. Throws InputError naming the segment whose timing length is zero
// (the arm turns at the centre with r_floor = 0).
PolarTrack polyline_polar_track(const ThetaRhoPath& path, double r_floor);

// Every step of both motors along the track (as digitize() for the polar machine).
DigitizeResult digitize(const ThetaRhoTrack& track, const Grid& grid, StepRule rule, const SpeedProfile& profile,
                        StepSink* sink);

// The track of a theta-rho polyline (as ThetaRhoTrack::build from the path, or polyline_polar_track for c = 0),
// streamed: it holds the path's vertices (by reference) and a summary (length, ranges, the first and last
// pieces), and makes each piece from its segment's two vertices when it is visited, so its memory does not grow
// with the path (an AxisTrack holds about 1 KB a piece). Every piece it visits is bit for bit the piece the held
// track has at that index, s0 included, so digitizing it gives the same steps at the same times.
// The path must outlive the track.
class PolylineTrack {
 public:
  // One pass over the segments (InputError as polyline_polar_track; c must be finite).
  PolylineTrack(const ThetaRhoPath& path, double c, double r_floor);

  const ThetaRhoPath& path() const { return *path_; }
  double coupling() const { return c_; }
  double timing_radius() const { return r_floor_; }
  size_t size() const { return n_; }  // pieces
  double length() const { return length_; }
  bool closed() const { return closed_; }
  int winding() const { return winding_; }
  // Ranges of the axis coordinates (0: the radial motor q = rho + c theta, 1: theta), as AxisTrack's.
  TrackExtent q_min(int a) const { return qmin_[a]; }
  TrackExtent q_max(int a) const { return qmax_[a]; }
  // Ranges of the ball's radius rho, as the polar track's (c = 0) r_min() and r_max().
  TrackExtent r_min() const { return rmin_; }
  TrackExtent r_max() const { return rmax_; }
  const TrackPiece& front() const { return front_; }
  const TrackPiece& back() const { return back_; }

  // Visits the pieces in order, f(index, piece), s0 set. `polar`: the pieces of the polar track (c = 0: q0 = rho)
  // instead of the coupled arm's.
  template <class F>
  void for_each(F&& f, bool polar = false) const {
    visit([](void* ctx, size_t i, const TrackPiece& pc) { (*static_cast<std::remove_reference_t<F>*>(ctx))(i, pc); },
          const_cast<void*>(static_cast<const void*>(&f)), polar);
  }
  // Piece i (made by a walk of the pieces before it: for error messages and single look-ups).
  TrackPiece piece(size_t i, bool polar = false) const;

 private:
  void visit(void (*f)(void*, size_t, const TrackPiece&), void* ctx, bool polar) const;

  const ThetaRhoPath* path_;
  double c_, r_floor_;
  size_t n_ = 0;
  double length_ = 0.0;
  bool closed_ = false;
  int winding_ = 0;
  TrackExtent qmin_[2]{}, qmax_[2]{}, rmin_{}, rmax_{};
  TrackPiece front_, back_;
};

// Every step of both motors along a streamed polyline track: the same result and the same steps, in the same
// order and at the same times, as digitize() of ThetaRhoTrack::build(path, c, r_floor) (or, for c = 0, of
// polyline_polar_track), in memory that does not grow with the path.
DigitizeResult digitize(const PolylineTrack& track, const Grid& grid, StepRule rule, const SpeedProfile& profile,
                        StepSink* sink);

}  // namespace polarcam
