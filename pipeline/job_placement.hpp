#pragma once
// Job -> pole placement glue (docs/area-error.md, docs/optimum-loading.md): the pole problem of a job, with its
// dynamics when asked, and the area error and dynamics of the job at any placement, through the production pipeline
// (make_job_path, digitize, analyze_case), so that what `optimize` reports is what `error` and `analyze` would say.
#include "job/job.hpp"
#include "pipeline/job_analysis.hpp"
#include "optimize/placement.hpp"

namespace polarcam {

// The tool path with the machine pole at the contour pole, the grid and rule of the job, opt's objective, segments
// and pole-outside constraint. With `dynamics`: the job's machine model, load, motion and tool side (InputError
// naming the job file when the machine has none), and, when opt.torque_limit, the limit 1 / safety factor.
PoleProblem job_pole_problem(const Job& job, const PlacementOptions& opt, bool dynamics);

// The exact area error (m^2) of the job digitized at a placement, with its own grid and work area.
double job_area(const Job& job, const Placement& pl);

// The job at a placement, analysed as `analyze` does (its speed and load; no speed search).
CaseResult job_dynamics_at(const Job& job, const Placement& pl);

// The direction of O1 - O in [0, 2 pi) (the contour pole seen from the machine pole).
double opposite_beta(const Placement& pl);

}  // namespace polarcam
