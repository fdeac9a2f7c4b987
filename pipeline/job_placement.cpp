#include "pipeline/job_placement.hpp"

#include <cmath>
#include <numbers>

#include "cam/error.hpp"

namespace polarcam {

PoleProblem job_pole_problem(const Job& job, const PlacementOptions& opt, bool dynamics) {
  Job at0 = job;
  at0.placement = Placement{0.0, 0.0};
  const ToolPathPtr path0 = make_job_path(at0);
  PoleProblem problem;
  try {
    problem = make_pole_problem(path0, job.machine.grid, job.motion.rule, opt.objective, opt.segments, opt.pole_outside);
    if (dynamics) {
      if (!job.machine.dynamics)
        throw InputError("the machine has no dynamics: give carriage_mass, arm_inertia, arm_friction_torque, "
                         "worm_factor, screw_factor, screw_lead and [machine.motor] (docs/dynamics.md)");
      const DynamicsSetup setup = dynamics_setup(job, DynamicsCase{std::nullopt, job.load});
      const int side = tool_side_sign(*job.contour, job.tool, job.motion.travel);
      problem.torque = make_torque_problem(*job.machine.dynamics, setup, side);
      if (opt.torque_limit) problem.torque_limit = 1.0 / job.safety_factor;
    }
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
  return problem;
}

double job_area(const Job& job, const Placement& pl) {
  Job j = job;
  j.placement = pl;
  PolarAreaMeter meter;
  const ToolPathPtr path = make_job_path(j);
  PolarTrack track;
  try {
    track = PolarTrack::build(*path);
    meter.reset(track, j.machine.grid);
    auto prof = make_job_profile(j, *path, track.length());
    const DigitizeResult d = digitize(track, j.machine.grid, j.motion.rule, *prof, &meter);
    return meter.finish(d.start_n, d.start_m).area_m2;
  } catch (const InputError& e) {
    throw InputError("at C = " + std::to_string(pl.C) + " m, beta = " + std::to_string(pl.beta) +
                     " rad: " + e.what(), job.file);
  }
}

CaseResult job_dynamics_at(const Job& job, const Placement& pl) {
  Job j = job;
  j.placement = pl;
  const PreparedDynamics prep = prepare_dynamics(j);
  AnalysisOptions o;
  o.keep_series = false;
  return analyze_case(j, prep, DynamicsCase{std::nullopt, j.load}, o, false);
}

double opposite_beta(const Placement& pl) {
  if (!(pl.C > 0.0)) return 0.0;
  double b = std::fmod(pl.beta + std::numbers::pi, 2.0 * std::numbers::pi);
  if (b < 0.0) b += 2.0 * std::numbers::pi;
  return b;
}

}  // namespace polarcam
