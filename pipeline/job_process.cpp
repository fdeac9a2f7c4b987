#include "pipeline/job_process.hpp"

#include <algorithm>

#include "cam/error.hpp"

namespace polarcam {

ProcessRun run_process(const Job& job) {
  if (!job.milling)
    throw InputError("the job has no milling cut: give [load] kind = \"milling\" (docs/process.md)", job.file);
  const MillingSetup& m = *job.milling;
  const process::MillingPath& mp = *m.path;
  ProcessRun r;
  r.setup = &m;
  r.mode = mp.mode();
  r.length_m = mp.length();
  if (job.motion.constant_force) {
    r.constant_force = true;
    r.limits = constant_force_limits(job);
    const process::ConstantForceSchedule sch = constant_force_job_schedule(job);
    r.stretches = sch.stretches;
    r.total_time_s = sch.total_time_s;
    double t = 0.0;
    for (size_t k = 0; k < sch.stations.size(); ++k) {
      const process::FeedStation& f = sch.stations[k];
      if (k > 0) t += 2.0 * (f.s - sch.stations[k - 1].s) / (f.v + sch.stations[k - 1].v);
      r.points.push_back({f.s, t, f.v, mp.at_station(f.station, f.v), f.binding});
    }
  } else {
    const SpeedProfilePtr prof = make_job_profile(job, mp.length());
    for (size_t k = 0; k < mp.stations().size(); ++k) {
      const double s = mp.stations()[k].s, v = prof->speed_at(s);
      r.points.push_back({s, prof->time_at(s), v, mp.at_station(k, v), std::nullopt});
    }
    r.total_time_s = prof->total_time();
  }
  for (const ProcessPoint& p : r.points) {
    r.max_mean_force_N = std::max(r.max_mean_force_N, p.force.mean_resultant_N);
    r.max_peak_force_N = std::max(r.max_peak_force_N, p.force.peak_resultant_N);
    r.max_tooth_force_N = std::max(r.max_tooth_force_N, p.force.peak_tooth_N);
    r.max_normal_force_N = std::max(r.max_normal_force_N, p.force.peak_normal_N);
    r.max_feed_per_tooth_m = std::max(r.max_feed_per_tooth_m, p.force.feed_per_tooth_m);
  }
  const process::ToolLimits& l = m.limits;
  auto over = [&](double v, std::optional<double> lim, const char* name) {
    if (lim && v > *lim * (1.0 + 1e-9)) r.exceeded.push_back(name);
  };
  over(r.max_peak_force_N, l.breakage_force_N, "breakage_force");
  over(r.max_peak_force_N, l.shank_force_limit_N, "shank_force");
  over(r.max_tooth_force_N, l.tooth_force_limit_N, "tooth_force");
  over(r.max_normal_force_N, l.deflection_force_limit_N, "deflection_force");
  over(r.max_feed_per_tooth_m, l.feed_per_tooth_limit_m, "feed_per_tooth");
  return r;
}

}  // namespace polarcam
