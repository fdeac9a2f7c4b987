#include "pipeline/job_analysis.hpp"

#include "pipeline/job_tape.hpp"

#include "cam/error.hpp"

namespace polarcam {

PreparedDynamics prepare_dynamics(const Job& job) {
  if (!job.machine.dynamics)
    throw InputError(job.file +
                     ": the machine has no dynamics: give carriage_mass, arm_inertia, arm_friction_torque, " +
                     "worm_factor, screw_factor, screw_lead and [machine.motor] (docs/dynamics.md)");
  PreparedDynamics p;
  p.path = make_job_path(job);
  try {
    p.track = job_polar_track(job, *p.path);
    p.theta_shift = place_on_grid(p.track, job.machine.grid);
    p.side = tool_side_sign(*job.contour, job.tool, job.motion.travel);
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
  return p;
}

MotionLaw motion_law(const Job& job, std::optional<double> speed) {
  MotionLaw m;
  m.speed = job.motion.speed;
  m.accel = job.motion.accel;
  m.table = job.motion.table;
  if (speed) {
    if (!m.table.empty()) throw InputError("a speed override needs a job with a constant speed, not a speed_profile");
    if (!(*speed > 0.0)) throw InputError("the speed must be positive");
    m.speed = *speed;
  }
  return m;
}

PlacedPath placed_path(const PreparedDynamics& prep) {
  return PlacedPath{prep.path.get(), &prep.track, prep.theta_shift, prep.side};
}

DynamicsSetup dynamics_setup(const Job& job, const DynamicsCase& c) {
  if (!job.machine.dynamics) throw InputError("the machine has no dynamics", job.file);
  try {
    DynamicsSetup s;
    s.machine = &*job.machine.dynamics;
    s.load = make_load(c.load);
    s.motion = motion_law(job, c.speed);
    s.safety_factor = job.safety_factor;
    return s;
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
}

CaseResult analyze_case(const Job& job, const PreparedDynamics& prep, const DynamicsCase& c, const AnalysisOptions& opt,
                        bool search_speed, const Progress& progress) {
  report_progress(progress, 0.0);
  CaseResult r;
  r.spec = c;
  const DynamicsSetup setup = dynamics_setup(job, c);
  r.load = setup.load;
  if (setup.motion.table.empty()) r.speed = setup.motion.speed;
  try {
    CaseDynamics d = analyze_dynamics(placed_path(prep), setup, opt, search_speed);
    r.analysis = std::move(d.analysis);
    r.verdict = d.verdict;
    r.search = d.search;
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
  report_progress(progress, 1.0);
  return r;
}

}  // namespace polarcam
