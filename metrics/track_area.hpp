#pragma once
// Areas swept by a track, for each piece a Chebyshev series on t in [-1, 1] (g, h, G, H as in track_view.hpp):
//   polar:      Astar(t) = integral from -1 to t of (r^2 - r_a^2) / 2 * dtheta/dt dt    (m^2),
//   Cartesian:  Astar(t) = integral from -1 to t of (y - y_a) * dx/dt dt                  (m^2),
// r_a (y_a) the piece's height at t = -1. Half the integral of r^2 dtheta (the integral of y dx) between two points
// of a piece is then Astar(t1) - Astar(t0) + r_a^2 (theta1 - theta0) / 2 (+ y_a (x1 - x0)). Subtracting the
// height at the piece's start keeps the series small, so differences of nearby values keep their digits. The
// products of the series are formed exactly (degree up to 48) and chopped where the tail falls below rounding, so
// the series is as accurate as the track itself.
#include <array>
#include <vector>

#include "metrics/track_view.hpp"

namespace polarcam {

inline constexpr int kLongChebMaxDegree = 64;

// A Chebyshev series of up to kLongChebMaxDegree + 1 coefficients on t in [-1, 1].
struct LongCheb {
  int deg = 0;
  std::array<double, kLongChebMaxDegree + 1> c{};
  double operator()(double t) const {
    double b1 = 0.0, b2 = 0.0;
    const double tt = 2.0 * t;
    for (int k = deg; k >= 1; --k) {
      const double b0 = (c[k] - b2) + tt * b1;  // c - b2 is off the critical path
      b2 = b1;
      b1 = b0;
    }
    return (c[0] - b2) + t * b1;
  }
};

// Astar of every piece of the track, in the order of its pieces, appended to `out` after clearing it (reuses its
// storage).
void sector_area_series(const sweep::TrackView& track, std::vector<LongCheb>& out);
std::vector<LongCheb> sector_area_series(const sweep::TrackView& track);

}  // namespace polarcam
