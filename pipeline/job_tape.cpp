#include "pipeline/job_tape.hpp"

#include "pipeline/job_analysis.hpp"
#include "job/job_milling.hpp"
#include "job/pattern.hpp"

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

bool job_lifts_tool(const Job& job) { return job.machine.tool_lift && job.parts.size() > 1; }

double job_rapid_speed(const Job& job) {
  if (job.machine.rapid_speed) return *job.machine.rapid_speed;
  return job.motion.table.empty() ? job.motion.speed : job.motion.table.front().v;
}

namespace {

// Adds a piece's steps to the whole tape's result.
void add_piece(DigitizeResult& all, const DigitizeResult& r, int64_t t0) {
  for (auto [a, p] : {std::pair{&all.radial, &r.radial}, std::pair{&all.angular, &r.angular}}) {
    a->plus += p->plus;
    a->minus += p->minus;
    a->max_rate_hz = std::max(a->max_rate_hz, p->max_rate_hz);
    if (p->min_interval_ns >= 0 && (a->min_interval_ns < 0 || p->min_interval_ns < a->min_interval_ns))
      a->min_interval_ns = p->min_interval_ns;
  }
  if (r.radial.steps() + r.angular.steps() > 0) all.last_step_ns = t0 + r.last_step_ns;
  all.path_length_m += r.path_length_m;
}

DigitizedJob digitize_lifting(const Job& job, StepSink* sink) {
  DigitizedJob d;
  LiftedJob L;
  const Grid& grid = job.machine.grid;
  const double c = job.machine.coupling;
  const double rapid_v = job_rapid_speed(job);
  const double rapid_floor = job.machine.max_angular_speed ? rapid_v / *job.machine.max_angular_speed : 0.0;
  DigitizeResult& all = d.result;
  int64_t node[2] = {0, 0};
  int64_t t = 0;  // ns on the tape's clock
  for (size_t k = 0; k < job.parts.size(); ++k) {
    const std::string which = "contour " + std::to_string(k + 1) + " of " + std::to_string(job.parts.size());
    try {
      ToolPathPtr path = make_tool_path(job.parts[k], job.placement, job.tool, job.motion.travel);
      PolarTrack tr = PolarTrack::build(*path);
      const SpeedProfilePtr prof = make_job_profile(job, tr.length());
      std::optional<ThetaRhoTrack> arm;
      if (c != 0.0) arm = ThetaRhoTrack::build(*path, c);
      const AxisTrack& walk = arm ? static_cast<const AxisTrack&>(*arm) : tr;
      DigitizeResult r;
      if (k == 0) {
        r = digitize_arm(walk, c, grid, job.motion.rule, *prof, sink);
        all.start_n = r.start_n;
        all.start_m = r.start_m;
        all.theta_shift = r.theta_shift;
        d.path = path;
        d.profile = prof;
      } else {
        // the rapid from where the last contour ended to this one's start, on the arm's nearest turn
        const TrackPiece& last = L.tracks.back().pieces().back();
        const ThetaRho a{last.q_b[1] + L.shifts.back(), last.q_b[0]};
        const TrackPiece& first = tr.pieces().front();
        const double shift =
            2.0 * std::numbers::pi * std::nearbyint((a.theta - first.q_a[1]) / (2.0 * std::numbers::pi));
        const ThetaRho b{first.q_a[1] + shift, first.q_a[0]};
        if (sink) sink->tool(false, t);
        RapidMove mv{a, b};
        if (a.theta != b.theta || a.rho != b.rho) {
          ThetaRhoPath seg({a, b}, false, "rapid move");
          const PolarTrack rt = polyline_polar_track(seg, rapid_floor);
          const SpeedProfilePtr rprof = make_constant_speed(rapid_v, rt.length());
          DigitizeResult rr;
          if (c == 0.0) {
            rr = digitize_arm_from(rt, 0.0, grid, job.motion.rule, *rprof, sink, 0.0, node, t);
          } else {
            const ThetaRhoTrack rarm = ThetaRhoTrack::build(seg, c, rapid_floor);
            rr = digitize_arm_from(rarm, c, grid, job.motion.rule, *rprof, sink, 0.0, node, t);
          }
          add_piece(all, rr, t);
          node[0] = rr.end_n;
          node[1] = rr.end_m;
          t += rr.duration_ns;
          mv.length_m = theta_rho_segment_length(a, b);
          mv.duration_s = static_cast<double>(rr.duration_ns) * 1e-9;
          mv.steps = rr.radial.steps() + rr.angular.steps();
          L.rapid_length_m += mv.length_m;
          L.rapid_time_s += mv.duration_s;
          L.rapid_steps += mv.steps;
          L.rapids.push_back(mv);
        }
        if (sink) sink->tool(true, t);
        r = digitize_arm_from(walk, c, grid, job.motion.rule, *prof, sink, shift, node, t);
      }
      L.shifts.push_back(r.theta_shift);
      add_piece(all, r, t);
      L.drawn_length_m += r.path_length_m;
      node[0] = r.end_n;
      node[1] = r.end_m;
      t += r.duration_ns;
      L.paths.push_back(std::move(path));
      L.tracks.push_back(std::move(tr));
    } catch (const InputError& e) {
      throw InputError(which + ": " + e.message(), e.place()).in_file(job.file);
    }
  }
  all.end_n = node[0];
  all.end_m = node[1];
  all.duration_ns = t;
  all.duration_s = static_cast<double>(t) * 1e-9;
  d.track = L.tracks.front();
  d.lifted = std::move(L);
  return d;
}

}  // namespace

DigitizedJob digitize_job(const Job& job, StepSink* sink, const Progress& progress) {
  if (job_lifts_tool(job)) return digitize_lifting(job, sink);
  DigitizedJob d;
  d.path = make_job_path(job);
  const double c = job.machine.coupling;
  // a theta-rho polyline: one streamed track of the arm's motors (the polar track's pieces differ only in q0)
  const ThetaRhoPath* trp = job_theta_rho_path(*d.path);
  if (trp) check_pattern_travel(trp->vertices(), job.machine.grid.dtheta, job.file);
  if (trp)
    d.polyline.emplace(in_file(job.file, [&] { return PolylineTrack(*trp, c, job_timing_radius(job)); }));
  else
    d.track = job_polar_track(job, *d.path);
  try {
    if (job.motion.time_optimal && (trp || c != 0.0))
      throw InputError("[motion] speed_profile = \"time-optimal\" needs a plain polar machine and path (no coupling, "
                       "no theta-rho pattern)", job.file);
    if (job.motion.constant_force)
      d.profile = constant_force_job_profile(job, trp ? d.polyline->length() : d.track.length());
    else
      d.profile = job.motion.time_optimal ? time_optimal_job_profile(job)
                                          : make_job_profile(job, *d.path, trp ? d.polyline->length() : d.track.length());
    ProgressSink counted(sink, progress, d.profile->total_time());
    if (progress) sink = &counted;
    if (trp) {
      d.result = digitize(*d.polyline, job.machine.grid, job.motion.rule, *d.profile, sink);
    } else if (c == 0.0) {
      d.result = digitize(d.track, job.machine.grid, job.motion.rule, *d.profile, sink);
    } else {
      // the coupled arm's radial motor: its own track, the same arc length
      const ThetaRhoTrack arm = ThetaRhoTrack::build(*d.path, c);
      d.result = digitize(arm, job.machine.grid, job.motion.rule, *d.profile, sink);
    }
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
  report_progress(progress, 1.0);
  return d;
}

PathRanges path_ranges(const DigitizedJob& d) {
  PathRanges pr;
  auto take = [&](const PolarTrack& tr, double shift, bool first) {
    const double lo = tr.r_min().value, hi = tr.r_max().value;
    const double tlo = tr.theta_min().value + shift, thi = tr.theta_max().value + shift;
    pr.r_min = first ? lo : std::min(pr.r_min, lo);
    pr.r_max = first ? hi : std::max(pr.r_max, hi);
    pr.theta_min = first ? tlo : std::min(pr.theta_min, tlo);
    pr.theta_max = first ? thi : std::max(pr.theta_max, thi);
  };
  if (d.lifted) {
    for (size_t k = 0; k < d.lifted->tracks.size(); ++k) take(d.lifted->tracks[k], d.lifted->shifts[k], k == 0);
  } else if (d.polyline) {
    const PolylineTrack& tr = *d.polyline;
    pr.r_min = tr.r_min().value;
    pr.r_max = tr.r_max().value;
    pr.theta_min = tr.q_min(1).value + d.result.theta_shift;
    pr.theta_max = tr.q_max(1).value + d.result.theta_shift;
  } else {
    take(d.track, d.result.theta_shift, true);
  }
  return pr;
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
