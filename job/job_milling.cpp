#include "job/job_milling.hpp"

#include <cmath>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "job/job.hpp"
#include "job/tool_file.hpp"

namespace polarcam {

void bind_milling(Job& job) {
  const MillingLoadSpec& m = job.load.milling;
  auto setup = std::make_shared<MillingSetup>();
  setup->tool_file = m.tool_file;
  setup->tool = load_tool_file(m.tool_file);
  const process::Tool& t = setup->tool;
  const double R = 0.5 * t.diameter_m;
  if (std::abs(job.tool.radius - R) > 1e-9)
    throw InputError("[tool] radius is " + significant(job.tool.radius * 1e3, 6) + " mm but the milling tool " +
                         m.tool_file + " has a radius of " + significant(R * 1e3, 6) +
                         " mm: give the mill's radius (half its diameter)",
                     job.file);
  try {
    setup->limits = process::tool_limits(t);
    const double Sy = t.yield_strength_Pa.value_or(t.breaking_stress_Pa);
    // no cut reaches deeper than the tool stands out of its holder
    if (m.axial_depth > t.length_m)
      throw InputError("is " + significant(m.axial_depth * 1e3, 6) + " mm, deeper than the tool stands out of its holder (" +
                           significant(t.length_m * 1e3, 6) + " mm, [tool] length of " + m.tool_file + ")",
                       "load.axial_depth");
    if (t.tooth) {
      // the tooth limit for this cut's depth (Fussell & Gagne Eq. 9-13)
      if (m.axial_depth > t.tooth->length_m)
        throw InputError("is longer than the tool's teeth ([tooth] length of " + m.tool_file + ")", "load.axial_depth");
      setup->limits.tooth_force_limit_N = process::tooth_force_limit(*t.tooth, m.axial_depth, Sy, t.safety_factor);
      if (t.cut) {
        // the feed-per-tooth limit (Eq. 14-18) for this cut: its spindle speed, depth and width, the tool file's
        // material constant
        process::MillingCut cut = *t.cut;
        cut.spindle_speed_rad_s = m.spindle_speed;
        cut.axial_depth_m = m.axial_depth;
        cut.radial_depth_m = m.radial_width;
        setup->limits.feed_per_tooth_limit_m =
            process::feed_per_tooth_limit(*setup->limits.tooth_force_limit_N, t.diameter_m, t.teeth, cut);
      }
    }
    process::MillingPathSpec& spec = setup->spec;
    spec.cutter = {t.teeth, R, t.helix_angle_rad, m.axial_depth, m.K_t, m.K_r, m.K_a};
    spec.radial_width_m = m.radial_width;
    spec.spindle_speed_rad_s = m.spindle_speed;
    spec.tool_side = tool_side_sign(*job.contour, job.tool, job.motion.travel);
    spec.clockwise = m.clockwise;
    process::check_milling_path_spec(spec);
    const ToolPathPtr path = make_job_path(job);
    setup->path = std::make_shared<const process::MillingPath>(*path, spec);
  } catch (const InputError& e) {
    const std::string& p = e.place();
    // the models name their fields; in the job they are [load] keys
    if (!p.empty() && p.find('.') == std::string::npos && p.find('/') == std::string::npos)
      throw InputError(e.message(), job.file + ": [load] " + p);
    throw e.in_file(job.file);
  }
  std::shared_ptr<const process::MillingPath> mp = setup->path;
  job.load.milling.model = [mp](double s, double V) {
    const process::MillingForceAt f = mp->at(s, V);
    return ToolForce{f.feed_force_N, f.normal_force_N};
  };
  job.milling = std::move(setup);
}

process::ConstantForceLimits constant_force_limits(const Job& job) {
  if (!job.motion.constant_force || !job.milling)
    throw InputError("the job has no constant-force schedule: give [motion] speed_profile = \"constant-force\" and a "
                     "[load] kind = \"milling\"", job.file);
  const process::ToolLimits& tl = job.milling->limits;
  process::ConstantForceLimits l;
  l.nominal_force_N = job.motion.nominal_force;
  l.max_speed = job.motion.speed;
  l.max_acceleration = job.machine.max_acceleration;
  l.breakage_force_N = tl.breakage_force_N;
  l.shank_force_N = tl.shank_force_limit_N;
  l.tooth_force_N = tl.tooth_force_limit_N;
  l.deflection_force_N = tl.deflection_force_limit_N;
  l.feed_per_tooth_m = tl.feed_per_tooth_limit_m;
  l.entry_feed_per_tooth_m = tl.rapid_feed_per_tooth_m;
  l.entry_length_m = job.motion.entry_length ? *job.motion.entry_length : job.tool.radius;
  return l;
}

process::ConstantForceSchedule constant_force_job_schedule(const Job& job) {
  const process::ConstantForceLimits l = constant_force_limits(job);
  MillingSetup::ScheduleCache& c = job.milling->schedule_cache;
  const std::lock_guard<std::mutex> lock(c.mutex);
  if (!c.schedule || !c.limits || !(*c.limits == l)) {
    c.schedule = std::make_shared<const process::ConstantForceSchedule>(
        in_file(job.file, [&] { return process::constant_force_schedule(*job.milling->path, l); }));
    c.limits = l;
  }
  return *c.schedule;
}

SpeedProfilePtr constant_force_job_profile(const Job& job, double length) {
  const process::ConstantForceSchedule sch = constant_force_job_schedule(job);
  const double scale = length / sch.stations.back().s;
  std::vector<SpeedStation> st;
  st.reserve(sch.stations.size());
  for (const process::FeedStation& f : sch.stations) st.push_back({f.s * scale, f.v});
  st.back().s = length;
  return in_file(job.file, [&] { return make_table_speed_sq(std::move(st), length); });
}

}  // namespace polarcam
