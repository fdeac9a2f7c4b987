#pragma once
// Approximation of a curve by straight lines and circular arcs within a chord tolerance: what a CAM
// post-processor does before a conventional (Cartesian) NC control interpolates the part with its linear and
// circular DDAs. Each piece of the curve becomes a line through its end points when the curve stays within the
// tolerance of that line, else an arc through its end points and its parameter midpoint when the curve stays
// within the tolerance of that arc (sweep at most 90 degrees), else it is halved. Pieces never straddle a
// breakpoint of the curve, so the corners of a path stay sharp and its lines and arcs are found exactly.
// The segments chain end to end (each ends where the next starts) and their end points lie on the curve.
#include <cstddef>
#include <vector>

#include "cam/path.hpp"

namespace polarcam {

struct ArcFitOptions {
  double tolerance = 0.0;          // m: largest allowed distance from the curve to its line or arc
  double max_sweep = 1.5707963267948966;  // rad: longest arc (a quadrant, as an NC circular block; 1e-9 slack)
  size_t max_segments = 1'000'000; // more than this is an error (a tolerance too small for the curve)
};

struct ArcFit {
  std::vector<PathSegment> segments;
  double max_deviation = 0.0;  // m: largest distance from the curve to its segment, as measured
  size_t lines = 0, arcs = 0;
};

// Fits `c`. Throws InputError when the tolerance is not positive or the curve cannot be fitted within it.
ArcFit fit_lines_and_arcs(const Curve& c, const ArcFitOptions& opt);

// Distance from a point to a line segment or to a circular arc (to its nearer end when the point lies outside
// the arc's angular range).
double distance_to_segment(const PathSegment& s, Vec2 p);

// Length of a line or arc segment.
double segment_length(const PathSegment& s);

}  // namespace polarcam
