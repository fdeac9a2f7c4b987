#pragma once
// The figures of the operator report (`polarcam report`, docs/operator-report.md), drawn with app/plot (PLplot).
// Formatting only: every number comes from the job pipeline.
#include <cstdint>
#include <optional>
#include <vector>

#include "job/job.hpp"
#include "pipeline/job_analysis.hpp"
#include "pipeline/job_study.hpp"
#include "report/plot.hpp"
#include "optimize/pareto.hpp"

namespace polarcam::cli {

// Left: the work area (annulus sector), the tool path, the machine pole, the contour pole and the window of the
// right panel; right: the path and the machine's staircase in that window, magnified.
plot::Figure workarea_figure(const Job& job, const Curve& path, const Staircase& st, Vec2 window_centre,
                             double window_half);

// Torque needed (magnitude) and pull-out torque available, and the limit (pull-out / safety factor), per axis,
// along the path.
plot::Figure torque_figure(const Job& job, const CaseResult& c);

// Both schedules along the path (distance in mm): the speed, both motors' step rates with the drives' limits, and
// both torque ratios with the limit 1 / safety factor; the time-optimal schedule solid, the best constant speed
// dashed. `job_speed`: a constant-speed job's own speed, drawn in the speed panel.
plot::Figure schedules_figure(const Job& job, const ScheduleStudy& s, double limit, std::optional<double> job_speed);

// Points of the pole study drawn on the map.
struct PoleMark {
  Vec2 pole;  // O - O1 (m)
  const char* label;
  int color;   // palette index
  int marker;  // PLplot symbol
};

// The exact area error over machine-pole positions (mm^2, blank where the path leaves the work area), the line
// where the worst torque ratio reaches the limit, crosses at the poles where it is exceeded, the contour in its own
// frame and the marked poles.
plot::Figure pole_map_figure(const Job& job, const PoleSurvey& sv, double limit, const std::vector<Vec2>& contour,
                             const std::vector<PoleMark>& marks);

// Area error against the worst torque ratio: every surveyed pole, the front, the limit, the marked poles.
plot::Figure tradeoff_figure(const PoleSurvey& sv, const std::vector<ParetoPoint>& front, double limit,
                             const std::vector<std::pair<ParetoPoint, PoleMark>>& marks);

}  // namespace polarcam::cli
