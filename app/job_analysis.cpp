#include "app/job_analysis.hpp"

#include "cam/error.hpp"

namespace polarcam {
namespace {

Job with_speed(const Job& job, std::optional<double> speed, double factor) {
  Job j = job;
  if (speed) {
    if (!j.motion.table.empty())
      throw InputError("a speed override needs a job with a constant speed, not a speed_profile");
    if (!(*speed > 0.0)) throw InputError("the speed must be positive");
    j.motion.speed = *speed;
  }
  j.motion.speed *= factor;
  for (auto& st : j.motion.table) st.v *= factor;
  return j;
}

}  // namespace

PreparedDynamics prepare_dynamics(const Job& job) {
  if (!job.dynamics)
    throw InputError(job.file +
                     ": the machine has no dynamics: give carriage_mass, arm_inertia, arm_friction_torque, " +
                     "worm_factor, screw_factor, screw_lead and [machine.motor] (docs/dynamics.md)");
  PreparedDynamics p;
  p.path = make_job_path(job);
  try {
    p.track = PolarTrack::build(*p.path);
    p.theta_shift = place_on_grid(p.track, job.grid);
    p.side = tool_side_sign(*job.contour, job.tool, job.motion.travel);
  } catch (const InputError& e) {
    throw InputError(job.file + ": " + e.what());
  }
  return p;
}

CaseResult analyze_case(const Job& job, const PreparedDynamics& prep, const DynamicsCase& c, const AnalysisOptions& opt,
                        bool search_speed) {
  CaseResult r;
  r.spec = c;
  try {
    r.load = make_load(c.load);
    const Job j = with_speed(job, c.speed, 1.0);
    if (j.motion.table.empty()) r.speed = j.motion.speed;
    const MachineModel& m = *job.dynamics;
    auto run = [&](const Job& jj, const AnalysisOptions& o) {
      SpeedProfilePtr prof = make_job_profile(jj, prep.track.length());
      DynamicsInput in{prep.path.get(), &prep.track, prep.theta_shift, prof.get(), &m, &r.load, prep.side};
      return analyze_torques(in, o);
    };
    r.analysis = run(j, opt);
    r.verdict = judge(r.analysis, m, job.safety_factor);
    if (search_speed) {
      // The search samples at the default density (its maxima are refined, so they barely depend on it) and
      // checks its answer at the caller's density; only if that fails does it search again at that density.
      auto passes = [&](const AnalysisOptions& o) {
        return [&, o](double f) {
          if (f == 1.0) return r.verdict.go;
          try {
            return judge(run(with_speed(job, c.speed, f), o), m, job.safety_factor).go;
          } catch (const OutsideCurveError&) {
            return false;  // beyond the tabulated curve: not known to pass
          }
        };
      };
      AnalysisOptions quick;
      quick.keep_series = false;
      AnalysisOptions full = opt;
      full.keep_series = false;
      r.search = max_passing_speed_factor(passes(quick));
      if (r.search.factor && *r.search.factor != 1.0 && !passes(full)(*r.search.factor))
        r.search = max_passing_speed_factor(passes(full));
    }
  } catch (const InputError& e) {
    throw InputError(job.file + ": " + e.what());
  }
  return r;
}

}  // namespace polarcam
