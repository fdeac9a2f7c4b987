#pragma once
// The objective of pole placement, evaluated at one machine-pole position (docs/area-error.md).
// A pole position is the vector O - O1 from the contour pole to the machine pole (the thesis's C e^{j beta}),
// in metres. The tool path as the machine sees it is the path built at C = 0, moved by -(O - O1).
#include <memory>
#include <string>
#include <vector>

#include "cam/curve.hpp"
#include "digitizer/digitize.hpp"
#include "digitizer/grid.hpp"
#include "optimize/area_error.hpp"

namespace polarcam {

enum class PoleObjective { area, f1 };
const char* to_string(PoleObjective o);

// Point-in-polygon test of the contour (CGAL), for the "pole outside a closed contour" constraint.
class ContourInside {
 public:
  // `polygon`: the closed contour sampled finely, in the contour's frame.
  explicit ContourInside(std::vector<Vec2> polygon);
  ~ContourInside();
  ContourInside(const ContourInside&) = delete;
  ContourInside& operator=(const ContourInside&) = delete;
  // True when p lies inside or on the polygon.
  bool inside(Vec2 p) const;
  // Distance from p to the polygon's boundary (m).
  double boundary_distance(Vec2 p) const;
  const std::vector<Vec2>& polygon() const { return poly_; }

 private:
  std::vector<Vec2> poly_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct PoleProblem {
  CurvePtr path0;               // tool-centre path with the machine pole at the contour pole
  Grid grid;                    // resolution and work area
  StepRule rule = StepRule::nearest;
  PoleObjective objective = PoleObjective::area;
  int segments = 100;           // F1: chords of the piecewise-linear approximation
  std::vector<Vec2> f1_points;  // their end points, in the contour's frame (filled by make_pole_problem)
  std::shared_ptr<const ContourInside> keep_outside;  // set: the pole must stay outside this closed contour
  // The path as a fine polyline (contour frame) and the largest |coordinate| on it: poles closer to the path than
  // kPoleClearance (|coordinates| + |pole|) are not evaluated (see PoleEvaluator).
  std::vector<Vec2> polyline;
  double coordinate_scale = 0.0;
};

// Relative clearance between the path and the machine pole below which a pole is not evaluated: the digitizer's
// polar track cannot resolve a path that passes the pole at about 1 % of its coordinates (its convergence
// tolerance on r is relative to r while rounding is relative to the coordinates; it then subdivides without end).
inline constexpr double kPoleClearance = 0.02;

// Fills the derived fields. `pole_outside` needs a closed contour (throws InputError otherwise).
PoleProblem make_pole_problem(CurvePtr path0, const Grid& grid, StepRule rule, PoleObjective objective, int segments,
                              bool pole_outside);

struct PoleValue {
  bool computed = false;    // false: the path runs through the machine pole (nothing can be evaluated)
  double margin = 0.0;      // m: signed distance to the constraints' boundary (>= 0 feasible), +inf if none
  std::string why;          // the tightest constraint, for messages
  double value = 0.0;       // the objective (area in m^2, or F1)
  double area_m2 = -1.0;    // the exact area error when it was computed
  uint64_t steps = 0;
  bool feasible() const { return computed && margin >= 0.0; }
};

// Evaluates pole positions; holds the reusable buffers, so use one per thread. A pole closer to the path than
// kPoleClearance times (largest |coordinate| of the path + |pole|) is not evaluated (computed = false). The area is computed on the grid
// without its work-area limits (the staircase does not depend on them), so it is defined, and continuous in the
// large, on both sides of the work area's boundary; feasibility is the margin.
class PoleEvaluator {
 public:
  explicit PoleEvaluator(const PoleProblem& p);
  PoleValue evaluate(Vec2 pole);
  // Same, but nothing is digitized where the constraints are not met (maps).
  PoleValue evaluate_feasible(Vec2 pole);
  // The exact area error at a pole whatever the objective.
  PoleValue area(Vec2 pole);
  // Only the margin (no digitizing).
  PoleValue margin(Vec2 pole);

 private:
  PoleValue run(Vec2 pole, bool want_area, bool want_value, bool only_feasible = false);
  const PoleProblem& p_;
  Grid unlimited_;
  PolarAreaMeter meter_;
};

// Signed margin (m) of a track against the work area of `g`: the least of r - r_min (when r_min > 0),
// r_max - r and the angular room on the best branch (radians times the largest radius); +inf without limits.
double work_area_margin(const PolarTrack& track, const Grid& g, std::string* why = nullptr);

// A curve moved rigidly by `offset` (same parameter, derivatives, breakpoints).
CurvePtr translated(CurvePtr base, Vec2 offset);

}  // namespace polarcam
