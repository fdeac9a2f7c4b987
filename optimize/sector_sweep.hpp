#pragma once
// The area enclosed between a contour and a machine path, one angular sector at a time (docs/area-error.md).
//
// The closed cycle G = contour + end connector - machine path + start connector has a winding number w(x) at every
// point; the area error is the integral of |w| over the plane. Along a ray from the machine pole at angle phi,
// w changes only where the ray crosses G, so w(rho, phi) = sum of the orientations (+1 when G crosses the ray
// towards increasing phi, -1 otherwise) of the crossings beyond rho. Inside one grid sector
// [j dtheta, (j + 1) dtheta] (angles in grid units, g = (theta + shift) / dtheta, lambda = g - j in [0, 1]) every
// part of G is a strand: a curve met at most once by each ray. Between consecutive events (strand ends and
// crossings of strands) the strands keep their radial order, and the area there is
//   sum_j |W_j| (F_{j+1} - F_j),   F = (1/2) integral of r^2 dphi of each strand, F_0 = 0 at the pole,
// W_j the winding number between the j-th and (j+1)-th strand counted from the pole.
// Strands: contour pieces (monotone parts of the polar track), arcs about the pole (the polar staircase and the
// connectors) and straight segments (any other piecewise path, e.g. a Cartesian staircase).
#include <cstdint>
#include <vector>

#include "cam/vec2.hpp"
#include "digitizer/polar_track.hpp"
#include "optimize/track_area.hpp"

namespace polarcam::sweep {

// Angles in grid units: g = (theta + shift) / dtheta, where theta is the track's unwrapped angle and shift the
// whole turns that put the track on the machine's angular branch.
struct Frame {
  double dtheta = 0.0;
  double shift = 0.0;
};

struct Strand {
  enum Kind : uint8_t { contour, arc, segment };
  Kind kind = arc;
  int8_t sigma = 1;      // +1 when the cycle traverses the strand towards increasing lambda
  int64_t j = 0;         // sector (unwrapped)
  double l0 = 0, l1 = 1; // lambda range, l0 < l1
  // contour: a part of one track piece, monotone in r and theta; t0, t1 and r0, r1 at l0 and l1
  uint32_t piece = 0;
  double t0 = 0, t1 = 0, r0 = 0, r1 = 0;
  // arc
  double rho = 0;
  // segment: end points in the machine frame (metres)
  Vec2 a, b;
};

class SectorSolver {
 public:
  SectorSolver(const PolarTrack& track, const std::vector<LongCheb>& areas, Frame frame)
      : tr_(track), areas_(areas), fr_(frame) {}

  // Area (m^2) of |w| over the sector of the strands (all with the same sector key; sectors of different turns
  // that coincide in the plane may be mixed: lambda is what matters). Exact up to rounding and root finding.
  double area(const std::vector<Strand>& strands) const;

  // Contour helpers, shared with the fast path.
  // t on the strand's piece where lambda = l (the strand is monotone in theta).
  double contour_t_at(const Strand& s, double l) const;
  // lambda of a track point
  double lambda_at(uint32_t piece, double t, int64_t j) const;
  // t in [ta, tb] of piece where r = rho (r monotone there and rho strictly between the end values)
  double contour_t_at_radius(uint32_t piece, double ta, double tb, double rho) const;

 private:
  double radius(const Strand& s, double l) const;
  double half_r2_integral(const Strand& s, double la, double lb) const;  // F over [la, lb]
  void crossings(const Strand& c, const Strand& arc, std::vector<double>& ev) const;

  const PolarTrack& tr_;
  const std::vector<LongCheb>& areas_;
  Frame fr_;
};

}  // namespace polarcam::sweep
