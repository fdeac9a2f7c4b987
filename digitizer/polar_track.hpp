#pragma once
// The polar track: the tool-centre path as a polar machine sees it, r(u) and the unwrapped theta(u) about the
// machine pole, with arc length s(u): the axis track (axis_track.hpp) of the polar axis map,
//   q0 = r = |p|,  q1 = theta = atan2(y, x) unwrapped (continuous along the path),
// for a path whose origin is the machine pole. The digitizer, the error metrics and the dynamics read it.
#include <cmath>
#include <limits>
#include <numbers>

#include "cam/curve.hpp"
#include "digitizer/axis_track.hpp"

namespace polarcam {

// The polar axis map (track_builder.hpp): r and the unwrapped angle about the origin.
struct PolarMap {
  static constexpr double kTwoPi = 2.0 * std::numbers::pi;
  static constexpr double kEps = std::numeric_limits<double>::epsilon();
  static constexpr double kPoleDistance = 1e-9;  // m: a path this close to the pole passes through it
  static constexpr double kJump = 0.25 * std::numbers::pi;  // largest angle between neighbouring samples
  static constexpr const char* kFrame = "machine ";
  static constexpr const char* kSingular = "passes through the machine pole";
  static constexpr const char* kRough = "it passes too close to the machine pole or is not smooth";

  double scale = 0.0;  // the rounding scale of the path's numbers (Curve::rounding_scale)

  static double unwrap(double a, double ref) { return a + kTwoPi * std::nearbyint((ref - a) / kTwoPi); }
  bool coords(Vec2 p, const double ref[2], double q[2], double& aux) const {
    q[0] = aux = std::sqrt(p.x * p.x + p.y * p.y);
    q[1] = unwrap(std::atan2(p.y, p.x), ref[1]);
    return q[0] >= kPoleDistance;
  }
  bool smooth(const double a[2], const double b[2]) const { return std::abs(b[1] - a[1]) <= kJump; }
  // A few units in the last place of the numbers r and theta come from: r itself and, for a placed path, the
  // pole distance and tool radius (the rounding scale), which dominate near the pole (aux_min: the least r).
  void tolerances(const double qa[2], const double span[2], double aux_min, double tol[2]) const {
    tol[0] = 16 * kEps * (std::abs(qa[0]) + span[0] + scale) + 1e-300;
    tol[1] = 16 * kEps * (std::abs(qa[1]) + span[1] + 1.0 + scale / aux_min) + 1e-300;
  }
  // A closed path ends exactly where it starts: same r, theta advanced by whole turns.
  int close(const double first[2], double last[2]) const {
    const double turns = std::nearbyint((last[1] - first[1]) / kTwoPi);
    last[0] = first[0];
    last[1] = first[1] + kTwoPi * turns;
    return static_cast<int>(turns);
  }
};

class PolarTrack : public AxisTrack {
 public:
  // Builds the track of `path`, whose origin is the machine pole. Throws InputError when the path is not finite,
  // passes through the pole, or cannot be resolved.
  static PolarTrack build(const Curve& path);

  TrackExtent r_min() const { return q_min(0); }
  TrackExtent r_max() const { return q_max(0); }
  TrackExtent theta_min() const { return q_min(1); }
  TrackExtent theta_max() const { return q_max(1); }

  // r and theta at (piece, t)
  double r(size_t piece, double t) const { return q(0, piece, t); }
  double theta(size_t piece, double t) const { return q(1, piece, t); }
};

}  // namespace polarcam
