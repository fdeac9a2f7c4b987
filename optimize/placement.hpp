#pragma once
// Pole placement for minimum contouring error (Sec. 4.4-4.9 of A. Fahim's thesis (1983); docs/area-error.md).
//
// Unknown: the machine pole's position O - O1 = C e^{j beta} relative to the contour pole. Objective: the exact
// area error of the job's staircase (or the thesis's surrogate F1). Constraints: the whole tool path inside the
// work area (r_min .. r_max, the angular range when there is one), optionally the pole outside a closed
// contour, optionally C or beta held at the job's value.
//
// Methods:
//  - hooke-jeeves: the thesis's direct search (Sec. 4.8, HOOKE of App. E) from the job's placement, steps of
//    0.125 in halved on failure, pattern factor 1; infeasible points are rejected.
//  - nlopt: a global stage (DIRECT-L), a local stage (COBYLA, the work-area margin as its constraint), and, for
//    the area, a sampling stage. The area error is a smooth trend plus a fluctuation of about 1 % that changes
//    completely when the pole moves by a few micrometres (which step falls where changes); the first two stages
//    see the mean of two evaluations 2 x DeltaR/2 apart, and the penalty lambda |margin| outside the work area,
//    so that they follow the trend and respect the boundary; the last stage evaluates a fixed pattern of points
//    in a disc of 20 DeltaR around the local optimum and keeps the best exact value, because the placement is a
//    number in the tape-making, not a fixture, and the fluctuation is as real as the trend.
// Every evaluation is deterministic and the result never depends on the number of threads.
#include <optional>
#include <string>
#include <vector>

#include "io/progress.hpp"

#include "cam/toolpath.hpp"
#include "optimize/pole_objective.hpp"

namespace polarcam {

enum class PoleMethod { automatic, nlopt, hooke_jeeves };
enum class PoleHold { none, C, beta };
const char* to_string(PoleMethod m);
const char* to_string(PoleHold h);

// The question: what the placement minimises and under which constraints (the [optimize] table of a job and
// the options of `polarcam optimize` that change the answer).
struct PlacementQuestion {
  PoleObjective objective = PoleObjective::area;  // area error, F1, balanced torque or worst torque ratio
  PoleHold hold = PoleHold::none;                 // keep C or beta at the job's value
  bool pole_outside = false;   // the machine pole outside a closed contour
  bool torque_limit = false;   // also keep every torque ratio within 1 / safety factor (the job's dynamics)
  bool pareto = false;         // the trade-off front of area error and worst torque ratio (optimize/pareto.hpp)
  int segments = 100;          // F1: chords of the piecewise-linear approximation
};

struct SearchBox {
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;  // pole positions O - O1 (m)
};

// The solver: how the search runs. Changes the effort and (within the search's tolerance) where it stops, never
// the question; the result does not depend on `threads`.
struct PlacementSolver {
  PoleMethod method = PoleMethod::automatic;  // hooke-jeeves for F1, nlopt for the others
  int max_evaluations = 0;     // 0: the default: nlopt on the area 1.2e7 / (steps of the job), within 200..4000;
                               // nlopt on F1 600; Hooke-Jeeves 400; balanced and torque 2000 (400 with C or beta
                               // held)
  double hj_step = 0.003175;   // m, Hooke-Jeeves: initial move, 0.125 in (HOKJEV's suggested initial move)
  double hj_reduction = 0.5;   // Hooke-Jeeves: factor on the step after a failed exploration
  double hj_acceleration = 1.0;  // Hooke-Jeeves: pattern-move factor
  double hj_min_step = 1e-6;   // m, Hooke-Jeeves: stop below this step
  int threads = 0;             // 0: all cores
  // nlopt: when given, the local stages only, from these placements (no coarse map, lattice, DIRECT-L or vertex
  // centres): for starts already known to lie in the right basins (the Pareto front's searches start from the
  // best surveyed poles)
  std::vector<Placement> local_starts;
  // The search box when the caller already has it (feasible_box of search_box, no hold): saves computing it (41 x 41
  // work-area margins).
  std::optional<SearchBox> box;
};

// Both, as the CLI and the job file give them (fields are read as PlacementOptions::objective etc.).
struct PlacementOptions : PlacementQuestion, PlacementSolver {};


struct PlacementStage {
  std::string name;
  int evaluations = 0;
  double best = 0.0;  // best objective value seen in the stage (feasible points)
};

struct PlacementResult {
  Placement placement;        // C >= 0, beta in [0, 2 pi)
  Vec2 pole;                  // O - O1
  PoleValue at;               // at the optimum: margin, objective, exact area error
  double f1 = 0.0;            // F1 (chords) at the optimum
  PoleMethod method = PoleMethod::nlopt;
  int evaluations = 0;        // objective evaluations (for the area, each one digitizes the path)
  std::vector<PlacementStage> stages;
  std::vector<Vec2> path;     // Hooke-Jeeves: the successive base points
  PoleValue start;            // at the job's placement
};

// Pole positions that can keep the path within r_max (without r_max: the contour's bounding box and its size
// again on every side). Throws InputError when the contour cannot fit within r_max at all.
SearchBox search_box(const PoleProblem& p);

// The part of `box` where the geometric constraints (the work area, the pole outside the contour) can be met, from
// their margins on an n x n lattice (no digitizing, no torques), widened by one lattice step and clipped to `box`;
// `box` itself when no lattice point is feasible. A torque limit is not checked: the poles that meet it lie inside
// the work area's feasible part, so the box holds them too, and the searches check the limit where they evaluate.
SearchBox feasible_box(const PoleProblem& p, const SearchBox& box, int n, int threads, const Progress& progress = {});

// `progress`: the share of the search's evaluation budget spent (1 at the end).
PlacementResult optimize_placement(const PoleProblem& p, const Placement& start, const PlacementOptions& o,
                                   const Progress& progress = {});

struct ObjectiveMap {
  SearchBox box;
  int nx = 0, ny = 0;
  std::vector<double> value;   // [iy * nx + ix]: the objective (area m^2 or F1); NaN where infeasible
  std::vector<double> area;    // the area (m^2) where computed, NaN elsewhere
  std::vector<double> margin;  // m
};

// The objective on a regular grid of pole positions (corners included), computed on `threads` threads.
// `progress`: the share of the poles evaluated (the grids below too).
ObjectiveMap objective_map(const PoleProblem& p, const SearchBox& box, int nx, int ny, int threads,
                           const Progress& progress = {});

// Everything at each pole of a regular grid (corners included): the margin everywhere, and where the work area
// (and pole-outside) constraints are met the exact area error and, when the problem has dynamics, the torques
// (PoleEvaluator::full). Computed on `threads` threads; the result does not depend on their number.
struct PoleSurvey {
  SearchBox box;
  int nx = 0, ny = 0;
  std::vector<PoleValue> cells;  // [iy * nx + ix]
  Vec2 pole(int ix, int iy) const;
};
PoleSurvey survey_poles(const PoleProblem& p, const SearchBox& box, int nx, int ny, int threads,
                        const Progress& progress = {});

// PoleEvaluator::full at each pole, in parallel, results in input order.
std::vector<PoleValue> evaluate_poles(const PoleProblem& p, const std::vector<Vec2>& poles, int threads,
                                      const Progress& progress = {});

int default_threads();

}  // namespace polarcam
