#pragma once
// Readers for point lists users already have. Both return points in metres in the contour frame.
//  - CSV: one "x,y" pair per line (comma, semicolon, tab or spaces); blank lines, '#' comments and a single
//    non-numeric header line are skipped. Values are in `unit_m` metres.
//  - theta-rho (.thr), the sand-table format: "theta rho" per line, theta in radians (continuous, unwrapped),
//    rho normalised 0..1 and multiplied by `rho_scale_m`. Converted with x = rho cos(theta), y = rho sin(theta).
#include <string>
#include <vector>

#include "cam/vec2.hpp"

namespace polarcam {

std::vector<Vec2> read_points_csv(const std::string& path, double unit_m);
std::vector<Vec2> read_points_thr(const std::string& path, double rho_scale_m);

}  // namespace polarcam
