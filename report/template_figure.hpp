#pragma once
// Fig. 3.2 of A. Fahim's thesis (Sec. 3.5): the template digitizer's contouring speed error |v* - 1| in percent
// against rho* = rho / H, one pair of curves per roller radius R_r* = R_r / H (Eq. 3.3a where the centre of
// curvature lies on the driven roller's side, Eq. 3.3b where it lies on the other), drawn over the radii the
// rollers can follow (digitizer/template_speed.hpp); Eq. 3.3b continues thin below them down to the 200 % the
// thesis quotes. Rendering only.
#include <optional>
#include <vector>

#include "report/plot.hpp"

namespace polarcam {

struct TemplateFigureOptions {
  std::vector<double> rr_stars;       // R_r* of each pair of curves
  double rho_star_max = 50.0;         // right end of the axis
  std::optional<double> mark_rho_star;  // a radius of curvature to mark on every curve (e.g. the thesis's example)
};

plot::Figure template_speed_figure(const TemplateFigureOptions& o);

}  // namespace polarcam
