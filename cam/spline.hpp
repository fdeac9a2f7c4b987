#pragma once
// Cubic spline through a list of points, as the thesis's digitizer did for discrete contour data (Sec. 2.3):
// parametric x(u), y(u) with u the cumulative chord length, natural end conditions for an open list and
// periodic ones for a closed list (the first point is not repeated at the end; a repeated one is dropped).
#include <vector>

#include "cam/curve.hpp"

namespace polarcam {

CurvePtr make_spline(const std::vector<Vec2>& points, bool closed, const std::string& source_name);

}  // namespace polarcam
