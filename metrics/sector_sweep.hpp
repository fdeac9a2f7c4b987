#pragma once
// The area enclosed between a contour and a machine path, one sector (polar) or strip (Cartesian) at a time
// (docs/area-error.md, docs/compare.md).
//
// The closed cycle G = contour + end connector - machine path + start connector has a winding number w(x) at every
// point; the area error is the integral of |w| over the plane. The sweep works in two coordinates of the plane:
// an abscissa g (the angle theta about the machine pole, or x) and a height h (the radius r, or y). Along a line
// of constant abscissa (a ray from the pole, or a vertical line), w changes only where the line crosses G, so w at a
// height is the sum of the orientations (+1 when G crosses the line towards increasing g, -1 otherwise) of the
// crossings above it. Inside one grid sector or strip [j width, (j + 1) width] (abscissa in grid units,
// lambda = g / width - j in [0, 1]) every part of G is a strand: a curve met at most once by each line. Between
// consecutive events (strand ends and crossings of strands) the strands keep their order in height, and the area
// there is
//   sum_j |W_j| (F_{j+1} - F_j),   F_0 = 0 at the pole (h = 0; for the Cartesian geometry any common base works),
// W_j the winding number between the j-th and (j+1)-th strand counted from below, and F of a strand
//   polar:      (1/2) integral of r^2 dtheta,
//   Cartesian:  integral of y dx.
// Strands: contour pieces (monotone parts of the track), levels of the staircase (arcs about the pole r = const of
// the polar staircase, horizontal segments y = const of the Cartesian one) and straight segments (connectors).
#include <cstdint>
#include <vector>

#include "cam/vec2.hpp"
#include "metrics/track_area.hpp"
#include "metrics/track_view.hpp"

namespace polarcam::sweep {

// Abscissa in grid units: lambda + j = (g + shift) / width, where g is the track's abscissa, width the sector's
// angle (rad) or the strip's width (m), and shift the whole turns that put a polar track on the machine's angular
// branch (0 for Cartesian).
struct Frame {
  double width = 0.0;
  double shift = 0.0;
  Geometry geo = Geometry::polar;
};

struct Strand {
  enum Kind : uint8_t { contour, level, segment };
  Kind kind = level;
  int8_t sigma = 1;      // +1 when the cycle traverses the strand towards increasing lambda
  int64_t j = 0;         // sector or strip (unwrapped)
  double l0 = 0, l1 = 1; // lambda range, l0 < l1
  // contour: a part of one track piece, monotone in g and h; t0, t1 and h0, h1 at l0 and l1
  uint32_t piece = 0;
  double t0 = 0, t1 = 0, h0 = 0, h1 = 0;
  // level: the staircase at height rho (an arc r = rho, or a segment y = rho)
  double rho = 0;
  // segment: end points in the machine frame (metres)
  Vec2 a, b;
};

class SectorSolver {
 public:
  SectorSolver(const TrackView& track, const std::vector<LongCheb>& areas, Frame frame)
      : tr_(track), areas_(areas), fr_(frame) {}

  // Area (m^2) of |w| over the sector or strip of the strands (all with the same key; polar sectors of different
  // turns that coincide in the plane may be mixed: lambda is what matters). Exact up to rounding and root finding.
  double area(const std::vector<Strand>& strands) const;

  // Contour helpers, shared with the fast path.
  // t on the strand's piece where lambda = l (the strand is monotone in g).
  double contour_t_at(const Strand& s, double l) const;
  // lambda of a track point
  double lambda_at(uint32_t piece, double t, int64_t j) const;
  // t in [ta, tb] of piece where h = rho (h monotone there and rho strictly between the end values)
  double contour_t_at_height(uint32_t piece, double ta, double tb, double rho) const;

 private:
  double height(const Strand& s, double l) const;
  double area_integral(const Strand& s, double la, double lb) const;  // F over [la, lb]
  void crossings(const Strand& c, const Strand& lv, std::vector<double>& ev) const;

  const TrackView& tr_;
  const std::vector<LongCheb>& areas_;
  Frame fr_;
};

}  // namespace polarcam::sweep
