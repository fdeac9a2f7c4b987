#include "pipeline/job_analysis.hpp"

#include "pipeline/job_tape.hpp"
#include "job/job_milling.hpp"

#include "cam/error.hpp"

#include <cmath>
#include <limits>
#include <numbers>

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
  if (job.motion.constant_force && !speed)  // the schedule's stations (V^2 linear between them on the tape)
    for (const process::FeedStation& f : constant_force_job_schedule(job).stations) m.table.push_back({f.s, f.v});
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

TimeOptimalLimits time_optimal_limits(const Job& job) {
  TimeOptimalLimits l;
  l.safety_factor = job.safety_factor;
  l.max_acceleration = job.machine.max_acceleration;
  l.max_angular_speed = job.machine.max_angular_speed;
  if (job.motion.time_optimal) l.max_speed = job.motion.speed;
  return l;
}

SpeedPlan plan_speed(const Job& job, const PreparedDynamics& prep, const LoadSpec& load, const AnalysisOptions& check) {
  if (!job.machine.dynamics) throw InputError("the machine has no dynamics", job.file);
  try {
    SpeedPlan plan;
    const TimeOptimalLimits lim = time_optimal_limits(job);
    plan.speed_cap = lim.max_speed;
    DynamicsSetup setup;
    setup.machine = &*job.machine.dynamics;
    setup.load = make_load(load);
    setup.safety_factor = job.safety_factor;
    const PlacedPath placed = placed_path(prep);
    plan.schedule = time_optimal_speed(placed, *setup.machine, setup.load, lim, check);
    // the best constant speed: from the cap down, or from the schedule's top speed up to 100 times it
    double top = 0.0;
    for (const SpeedStation& st : plan.schedule.stations) top = std::max(top, st.v);
    const double base = lim.max_speed ? *lim.max_speed : top;
    setup.motion.speed = base;
    const MachineModel& m = *setup.machine;
    // searched at the searches' sampling, confirmed at the default one (and searched again at that one if it fails)
    AnalysisOptions full;
    full.keep_series = false;
    auto passes_with = [&](const AnalysisOptions& ao, double f) {
      try {
        const TorqueAnalysis a = analyze_motion(placed, setup, ao, f);
        if (!judge(a, m, setup.safety_factor).go) return false;
        if (lim.max_angular_speed) {
          // the arm's largest angular speed, from the angular motor's largest step rate
          const double w = a.angular.step_rate.value * 2.0 * std::numbers::pi / (m.mech.k_theta * m.angular.steps_per_rev);
          if (w > *lim.max_angular_speed) return false;
        }
        return true;
      } catch (const OutsideCurveError&) {
        return false;
      }
    };
    auto passes_at = [&](const AnalysisOptions& ao) {
      return [&, ao](double f) { return passes_with(ao, f); };
    };
    const double most = lim.max_speed ? 1.0 : 100.0;
    const SpeedSearch sr = max_passing_speed_factor(passes_at(search_analysis()), passes_at(full), 1e-6, most);
    if (sr.factor) {
      plan.constant_speed = *sr.factor * base;
      plan.constant_capped = sr.capped;
      plan.constant_time = prep.track.length() / *plan.constant_speed;
    } else {
      plan.constant_time = std::numeric_limits<double>::infinity();
    }
    return plan;
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
}

SpeedProfilePtr time_optimal_job_profile(const Job& job) {
  const PreparedDynamics prep = prepare_dynamics(job);
  AnalysisOptions quick;
  quick.keep_series = true;
  try {
    return time_optimal_speed(placed_path(prep), *job.machine.dynamics, make_load(job.load), time_optimal_limits(job),
                              quick)
        .profile;
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
}

CaseResult analyze_case(const Job& job, const PreparedDynamics& prep, const DynamicsCase& c, const AnalysisOptions& opt,
                        bool search_speed, const Progress& progress) {
  report_progress(progress, 0.0);
  CaseResult r;
  r.spec = c;
  if (job.motion.time_optimal && !c.speed) {
    // the schedule, analysed as any motion is, and the best constant speed it is compared with
    SpeedPlan plan = plan_speed(job, prep, c.load, opt);
    r.load = make_load(c.load);
    r.analysis = plan.schedule.check;
    r.verdict = judge(r.analysis, *job.machine.dynamics, job.safety_factor);
    r.plan = std::move(plan);
    report_progress(progress, 1.0);
    return r;
  }
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
