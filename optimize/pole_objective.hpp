#pragma once
// The objective of pole placement, evaluated at one machine-pole position (docs/area-error.md).
// A pole position is the vector O - O1 from the contour pole to the machine pole (the thesis's C e^{j beta}),
// in metres. The tool path as the machine sees it is the path built at C = 0, moved by -(O - O1).
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cam/curve.hpp"
#include "digitizer/digitize.hpp"
#include "digitizer/grid.hpp"
#include "metrics/area_error.hpp"
#include "optimize/torque_objective.hpp"

namespace polarcam {

// area: the exact area error; f1: the thesis's surrogate (Ch. 4); balanced: the balanced-torque objective of
// Sec. 6.6.2 (max along the path of T_T / |1 - |T_R - T_theta||, torques normalised by the pull-out torques);
// torque: the worst torque ratio (max over the path and both axes), the torque end of the Pareto front.
enum class PoleObjective { area, f1, balanced, torque };
const char* to_string(PoleObjective o);
bool is_torque_objective(PoleObjective o);

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
  // The bounding box (x0, y0, x1, y1) of each run of kPolylineBlock segments of `polyline`: the clearance check skips
  // the runs whose box is farther than the clearance (filled by make_pole_problem; empty: every segment is checked).
  std::vector<std::array<double, 4>> polyline_blocks;
  // The dynamics (the balanced and torque objectives, and the torque limit need them).
  std::shared_ptr<const TorqueProblem> torque;
  // Set: a constraint: every torque ratio within this limit (normally 1 / safety factor) and no motor above its
  // maximum step rate. It enters the margin as kTorqueMarginLength per unit of relative excess (below).
  std::optional<double> torque_limit;
};

// A torque ratio 10 % over its limit counts as 1 mm outside the constraints' boundary in the margin (the searches
// need one signed margin; the scale sets how hard the global stage's penalty pushes back).
inline constexpr double kTorqueMarginLength = 0.01;

// Relative clearance between the path and the machine pole below which a pole is not evaluated: the digitizer's
// polar track cannot resolve a path that passes the pole at about 1 % of its coordinates (its convergence
// tolerance on r is relative to r while rounding is relative to the coordinates; it then subdivides without end).
inline constexpr double kPoleClearance = 0.02;
inline constexpr size_t kPolylineBlock = 64;

// Fills the derived fields. `pole_outside` needs a closed contour (throws InputError otherwise).
PoleProblem make_pole_problem(CurvePtr path0, const Grid& grid, StepRule rule, PoleObjective objective, int segments,
                              bool pole_outside);

struct PoleValue {
  bool computed = false;    // false: the path runs through the machine pole (nothing can be evaluated)
  double margin = 0.0;      // m: signed distance to the constraints' boundary (>= 0 feasible), +inf if none
  double geometry_margin = 0.0;  // m: the work area (and pole outside) alone
  std::string why;          // the tightest constraint, for messages
  double value = 0.0;       // the objective as the search sees it (area in m^2, F1, balanced, worst ratio; finite)
  double area_m2 = -1.0;    // the exact area error when it was computed
  uint64_t steps = 0;
  bool torque_computed = false;  // `torque` holds the dynamics at this pole
  TorqueValue torque;
  bool feasible() const { return computed && margin >= 0.0; }
};

// The value the searches see for a torque objective: the objective where it is finite (and below 1e3), otherwise
// 1e3 plus the largest ratio sum (a pole where the balanced objective is singular, or a motor has no pull-out torque
// left, ranks behind every other, and among themselves by how overloaded they are).
double torque_search_value(PoleObjective o, const TorqueValue& t);

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
  // The area error and, when the problem has dynamics, the torques, whatever the objective and constraints; the
  // margin as evaluate() has it.
  PoleValue full(Vec2 pole);
  // Only the margin (no digitizing).
  PoleValue margin(Vec2 pole);
  // Only the work area (and pole-outside) margin: no digitizing and no torques, whatever the torque limit (margin
  // and geometry_margin are the same).
  PoleValue geometry(Vec2 pole);

 private:
  PoleValue run(Vec2 pole, bool want_area, bool want_value, bool only_feasible = false, bool want_torque = false,
                bool torque_check = true);
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
