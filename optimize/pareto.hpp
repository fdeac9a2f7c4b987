#pragma once
// Accuracy against torque (docs/optimum-loading.md): over the pole positions that keep the path in the work area,
// the trade-off between the exact area error and the worst torque ratio (max over the path and both axes), as
// the set of poles no other pole beats in both (the Pareto front), and the pole of least area error whose every
// torque ratio stays within a limit.
//
// Method: a survey of the feasible box (both objectives at every lattice pole), the two ends (least area error, least
// worst ratio, each searched as in optimize_placement), and the epsilon-constraint problems in between (least area
// with the worst ratio held below levels spread evenly between the two ends); the non-dominated set of everything
// evaluated. The area error's fine structure (about 1 % when the pole moves by micrometres, docs/area-error.md)
// makes the front a staircase at that scale.
#include <functional>
#include <string>
#include <vector>

#include "optimize/placement.hpp"

namespace polarcam {

struct ParetoOptions {
  int survey = 25;            // lattice points per side of the survey
  int levels = 6;             // epsilon-constraint searches between the two ends
  int level_evaluations = 0;  // budget of each (0: the placement options' max_evaluations when set, otherwise a
                              // quarter of the default area budget, at least 150)
  int threads = 0;
};

struct ParetoPoint {
  Vec2 pole;                 // O - O1 (m)
  Placement placement;
  PoleValue v;               // area (area_m2) and torques (torque) at the pole
  std::string source;        // "survey", "least area", "least torque", "level k", "job"
};

struct ParetoResult {
  std::vector<ParetoPoint> front;  // by worst torque ratio increasing (area error decreasing)
  PoleSurvey survey;
  int evaluations = 0;
};

// `p` must have dynamics (p.torque); its objective and torque limit are ignored. `o` gives hold, threads and the
// end searches' budget.
// `progress`: the share done (the survey, the two ends, the levels, in that order).
ParetoResult pareto_front(const PoleProblem& p, const Placement& start, const PlacementOptions& o,
                          const ParetoOptions& po = {}, const Progress& progress = {});

// The survey's poles with both objectives computed (feasible, area and torques), as points.
std::vector<ParetoPoint> survey_points(const PoleSurvey& survey);

// Up to `most` placements of `known`'s points that meet `ok` and have both objectives, least `key` first, each at
// least `apart` (m) from those taken: the starts of local searches from a survey.
std::vector<Placement> starts_from(const std::vector<ParetoPoint>& known, const std::function<bool(const ParetoPoint&)>& ok,
                                   const std::function<double(const ParetoPoint&)>& key, double apart, size_t most);

// How far apart the local searches' starts from a survey are taken: one and a half cell diagonals.
double start_spacing(const PoleSurvey& survey);

// The non-dominated subset of points with both objectives computed (smaller is better in both), sorted by the worst
// torque ratio.
std::vector<ParetoPoint> non_dominated(std::vector<ParetoPoint> pts);

}  // namespace polarcam
