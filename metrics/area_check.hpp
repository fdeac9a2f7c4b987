#pragma once
// An independent, exact and slow computation of the area error with CGAL, for tests and cross-checks, of a polar
// staircase (below) or a Cartesian one (area_error_cgal_cartesian).
//
// The cycle is: the polyline from its first to its last point, a straight segment to the staircase's last node,
// the staircase backwards (radial segments, and arcs of circles about the machine pole at r = n dR), and a
// straight segment from its first node back to the polyline's start. Every point on it is rational (the rays
// theta = m dtheta are given rational unit vectors, exactly on the unit circle, within 1e-16 rad of the ray), the
// curves go into a CGAL arrangement of line segments and circular arcs (Arr_circle_segment_traits_2, exact
// arithmetic), the winding number of each face follows from crossing its edges, and the result is the sum over
// faces of |winding number| times area.
#include <cstdint>
#include <vector>

#include "cam/vec2.hpp"

namespace polarcam {

struct StairNode {
  int64_t n = 0, m = 0;
};

// `steps_per_rev` > 0 makes rays m and m + steps_per_rev identical.
double area_error_cgal(const std::vector<Vec2>& polyline, const std::vector<StairNode>& nodes, double dr,
                       double dtheta, int64_t steps_per_rev);

// The same for a Cartesian staircase (metrics/cartesian_error.hpp): nodes (i, j) at (i blu, j blu), consecutive
// nodes differing in one axis; every staircase segment is a line segment.
struct XYNode {
  int64_t i = 0, j = 0;
};
double area_error_cgal_cartesian(const std::vector<Vec2>& polyline, const std::vector<XYNode>& nodes, double blu);

}  // namespace polarcam
