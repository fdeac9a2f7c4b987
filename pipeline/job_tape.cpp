#include "pipeline/job_tape.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cam/error.hpp"
#include "digitizer/theta_rho.hpp"

#ifndef POLARCAM_VERSION
#define POLARCAM_VERSION "0.0.0"
#endif

namespace polarcam {

TapeHeader tape_header_for(const Job& job) {
  TapeHeader h;
  h.axes = TapeAxes::polar;
  h.rule = job.motion.rule == StepRule::nearest ? TapeRule::nearest : TapeRule::thesis;
  h.res[0] = job.machine.grid.dr;
  h.res[1] = job.machine.grid.dtheta;
  h.steps_per_rev = job.machine.grid.steps_per_rev;
  h.r_min = job.machine.grid.r_min;
  h.has_r_max = job.machine.grid.r_max.has_value();
  h.r_max = job.machine.grid.r_max.value_or(0.0);
  h.has_theta_range = job.machine.grid.theta_min.has_value();
  h.theta_min = job.machine.grid.theta_min.value_or(0.0);
  h.theta_max = job.machine.grid.theta_max.value_or(0.0);
  h.home[0] = job.machine.grid.home_n();
  h.home[1] = job.machine.grid.home_m();
  h.speed_mps = job.motion.table.empty() ? job.motion.speed : job.motion.table.front().v;
  nlohmann::ordered_json p;
  p["generator"] = std::string("polarcam ") + POLARCAM_VERSION;
  p["job"] = job.provenance;
  h.provenance = p.dump();
  return h;
}

void complete_header(TapeHeader& h, const DigitizeResult& r) {
  h.start[0] = r.start_n;
  h.start[1] = r.start_m;
  h.end[0] = r.end_n;
  h.end[1] = r.end_m;
  h.duration_ticks = static_cast<uint64_t>(r.duration_ns);
  h.closed = r.closed;
  h.returns_to_start = r.returns_to_start;
  h.path_length_m = r.path_length_m;
}

const ThetaRhoPath* job_theta_rho_path(const Curve& path) {
  const auto* tp = dynamic_cast<const ToolPath*>(&path);
  if (!tp || !tp->is_contour_itself()) return nullptr;
  return as_theta_rho_path(tp->contour());
}

double job_timing_radius(const Job& job) {
  if (!job.machine.max_angular_speed) return 0.0;
  double v = job.motion.speed;
  for (const SpeedStation& st : job.motion.table) v = std::max(v, st.v);
  return v / *job.machine.max_angular_speed;
}

PolarTrack job_polar_track(const Job& job, const Curve& path) {
  return in_file(job.file, [&] {
    if (const ThetaRhoPath* trp = job_theta_rho_path(path)) return polyline_polar_track(*trp, job_timing_radius(job));
    return PolarTrack::build(path);
  });
}

DigitizedJob digitize_job(const Job& job, StepSink* sink, const Progress& progress) {
  DigitizedJob d;
  d.path = make_job_path(job);
  d.track = job_polar_track(job, *d.path);
  try {
    d.profile = make_job_profile(job, *d.path, d.track.length());
    ProgressSink counted(sink, progress, d.profile->total_time());
    if (progress) sink = &counted;
    const double c = job.machine.coupling;
    if (c == 0.0) {
      d.result = digitize(d.track, job.machine.grid, job.motion.rule, *d.profile, sink);
    } else {
      // the coupled arm's radial motor: its own track, the same arc length
      const ThetaRhoPath* trp = job_theta_rho_path(*d.path);
      const ThetaRhoTrack arm = trp ? ThetaRhoTrack::build(*trp, c, job_timing_radius(job)) : ThetaRhoTrack::build(*d.path, c);
      d.result = digitize(arm, job.machine.grid, job.motion.rule, *d.profile, sink);
    }
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
  report_progress(progress, 1.0);
  return d;
}

std::vector<StepRateExcess> step_rate_excess(const Job& job, const DigitizeResult& r) {
  std::vector<StepRateExcess> out;
  if (!job.machine.dynamics) return out;
  const MachineModel& m = *job.machine.dynamics;
  const Grid& g = job.machine.grid;
  for (int axis = 0; axis < 2; ++axis) {
    const StepperMotor& motor = axis == 0 ? m.radial : m.angular;
    if (!motor.max_step_rate) continue;
    const double per = axis == 0 ? g.dr * m.mech.k_R * motor.steps_per_rev
                                 : g.dtheta * m.mech.k_theta * motor.steps_per_rev / (2.0 * std::numbers::pi);
    const double tape_rate = axis == 0 ? r.radial.max_rate_hz : r.angular.max_rate_hz;
    const double motor_rate = tape_rate * per;
    if (std::isfinite(per) && per > 0.0 && motor_rate > *motor.max_step_rate)
      out.push_back({axis, tape_rate, per, motor_rate, *motor.max_step_rate});
  }
  return out;
}

}  // namespace polarcam
