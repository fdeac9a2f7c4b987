#pragma once
// Reader for point lists users already have, in metres in the contour frame.
//  - CSV: one "x,y" pair per line (comma, semicolon, tab or spaces); blank lines, '#' comments and a single
//    non-numeric header line are skipped. Values are in `unit_m` metres.
// Theta-rho (.thr) files are patterns of their own, not point lists: cam/thr_file.hpp.
#include <string>
#include <vector>

#include "cam/vec2.hpp"

namespace polarcam {

std::vector<Vec2> read_points_csv(const std::string& path, double unit_m);

}  // namespace polarcam
