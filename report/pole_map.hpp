#pragma once
// Output of `polarcam optimize --map/--map-image`: the objective over machine-pole positions as CSV and as a
// topographic figure like Figures 4.9-4.11 of the thesis (the contour drawn, the optimum marked).
#include <string>
#include <vector>

#include "report/plot.hpp"
#include "optimize/placement.hpp"

namespace polarcam {

// x_mm,y_mm,C_mm,beta_rad,feasible,objective,area_error_mm2,margin_mm (objective: mm^2 for the area, F1 for f1);
// one row per pole position, x fastest; empty fields where there is no value.
std::string map_csv(const ObjectiveMap& m, PoleObjective objective);

// The filled contour map (mm), the contour in its own frame, the job's placement, the optimum and, for
// Hooke-Jeeves, its path.
plot::Figure map_figure(const ObjectiveMap& m, PoleObjective objective, const std::vector<Vec2>& contour,
                        const Placement& start, const PlacementResult& r, const std::string& title);

}  // namespace polarcam
