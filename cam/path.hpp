#pragma once
// Paths of straight lines and circular arcs (the vocabulary of G-code G1/G2/G3). The parameter is arc length.
// A closed path ends where it starts. offset_path() gives the tool-centre path at a signed distance
// (positive = left of the direction of travel): lines move parallel, arcs change radius, convex corners get a
// round arc about the corner (as a CAM system does), and a concave corner or an arc whose radius would vanish
// is an error, never a garbled path.
#include <vector>

#include "cam/curve.hpp"

namespace polarcam {

struct PathSegment {
  enum class Kind { line, arc } kind = Kind::line;
  Vec2 from, to;    // end points
  Vec2 center;      // arc only
  double sweep = 0; // arc only: signed angle, positive counter-clockwise
};

// Builds the segments of an arc from its start, centre and signed sweep.
PathSegment make_arc_segment(Vec2 from, Vec2 center, double sweep);
// An arc from `from` to `to` about `center` in the given direction; the end must lie on the circle
// (relative tolerance 1e-6).
PathSegment make_arc_segment_to(Vec2 from, Vec2 to, Vec2 center, bool ccw);

CurvePtr make_path(std::vector<PathSegment> segments, bool closed);

// Offsets the segments by `d` (metres, + left). Throws InputError naming the segment or corner that folds.
std::vector<PathSegment> offset_path(const std::vector<PathSegment>& segments, bool closed, double d);

// Segments of a path curve made by make_path (nullptr when the curve is not a path).
const std::vector<PathSegment>* path_segments(const Curve& c);

}  // namespace polarcam
