#include "report/process_report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "report/report_numbers.hpp"

namespace polarcam {

namespace {

using json = nlohmann::ordered_json;
constexpr double kDeg = 180.0 / std::numbers::pi;

json opt(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

using report_numbers::g;

}  // namespace

json process_json(const Job& job, const ProcessRun& r) {
  const MillingSetup& m = *r.setup;
  const MillingLoadSpec& ml = job.load.milling;
  json j;
  j["mode"] = to_string(r.mode);
  j["profile"] = r.constant_force ? "constant-force" : "job";
  j["cut"] = {{"tool_diameter_m", m.tool.diameter_m},
              {"teeth", m.tool.teeth},
              {"helix_angle_rad", m.tool.helix_angle_rad},
              {"spindle_speed_rad_s", ml.spindle_speed},
              {"axial_depth_m", ml.axial_depth},
              {"radial_width_m", ml.radial_width},
              {"K_t_Pa", ml.K_t},
              {"K_r_Pa", ml.K_r},
              {"K_a_Pa", ml.K_a},
              {"spindle_direction", ml.clockwise ? "cw" : "ccw"}};
  const process::ToolLimits& l = m.limits;
  j["limits"] = {{"breakage_force_N", l.breakage_force_N},
                 {"shank_force_limit_N", l.shank_force_limit_N},
                 {"tooth_force_limit_N", opt(l.tooth_force_limit_N)},
                 {"deflection_force_limit_N", opt(l.deflection_force_limit_N)},
                 {"feed_per_tooth_limit_m", opt(l.feed_per_tooth_limit_m)},
                 {"rapid_feed_per_tooth_m", l.rapid_feed_per_tooth_m}};
  if (r.limits) {
    j["nominal_force_N"] = r.limits->nominal_force_N;
    j["top_speed_mps"] = r.limits->max_speed;
    j["max_acceleration_mps2"] = opt(r.limits->max_acceleration);
    j["entry_length_m"] = r.limits->entry_length_m;
  }
  j["path_length_m"] = r.length_m;
  j["duration_s"] = r.total_time_s;
  j["max_mean_force_N"] = r.max_mean_force_N;
  j["max_peak_force_N"] = r.max_peak_force_N;
  j["max_tooth_force_N"] = r.max_tooth_force_N;
  j["max_normal_force_N"] = r.max_normal_force_N;
  j["max_feed_per_tooth_m"] = r.max_feed_per_tooth_m;
  j["exceeded"] = r.exceeded;
  json st = json::array();
  for (const process::FeedStretch& s : r.stretches)
    st.push_back({{"s0_m", s.s0}, {"s1_m", s.s1}, {"binding", process::to_string(s.binding)}});
  j["stretches"] = st;
  return j;
}

std::string process_text(const Job& job, const ProcessRun& r) {
  const MillingLoadSpec& ml = job.load.milling;
  const process::ToolLimits& l = r.setup->limits;
  std::string s = fmt::format("{}: milling {} ({} teeth, {} mm), axial depth {} mm, radial width {} mm, {} rev/min\n",
                              job.file, to_string(r.mode), r.setup->tool.teeth, g(r.setup->tool.diameter_m * 1e3),
                              g(ml.axial_depth * 1e3), g(ml.radial_width * 1e3),
                              g(ml.spindle_speed * 60.0 / (2.0 * std::numbers::pi)));
  if (r.limits)
    s += fmt::format("  constant force {} N, top feed {} mm/s\n", g(r.limits->nominal_force_N),
                     g(r.limits->max_speed * 1e3));
  s += fmt::format("  path {} mm in {} s\n", g(r.length_m * 1e3), g(r.total_time_s));
  s += fmt::format("  largest mean force {} N, peak {} N (breakage {} N, shank {} N)\n", g(r.max_mean_force_N),
                   g(r.max_peak_force_N), g(l.breakage_force_N), g(l.shank_force_limit_N));
  s += fmt::format("  largest tooth force {} N{}, perpendicular force {} N{}\n", g(r.max_tooth_force_N),
                   l.tooth_force_limit_N ? " (limit " + g(*l.tooth_force_limit_N) + " N)" : "",
                   g(r.max_normal_force_N),
                   l.deflection_force_limit_N ? " (limit " + g(*l.deflection_force_limit_N) + " N)" : "");
  s += fmt::format("  largest feed per tooth {} mm{}\n", g(r.max_feed_per_tooth_m * 1e3),
                   l.feed_per_tooth_limit_m ? " (limit " + g(*l.feed_per_tooth_limit_m * 1e3) + " mm)" : "");
  for (const process::FeedStretch& st : r.stretches)
    s += fmt::format("  s {} - {} mm: {}\n", g(st.s0 * 1e3), g(st.s1 * 1e3), process::describe(st.binding));
  for (const std::string& e : r.exceeded) s += "  EXCEEDED: " + e + "\n";
  return s;
}

std::string process_csv(const ProcessRun& r) {
  std::ostringstream os;
  os.precision(12);
  os << "s_m,t_s,speed_mm_per_s,feed_per_tooth_mm,engaged_angle_deg,feed_force_N,normal_force_N,mean_force_N,"
        "peak_force_N,peak_tooth_force_N,peak_normal_force_N,binding\n";
  for (const ProcessPoint& p : r.points)
    os << p.s << "," << p.t << "," << p.v * 1e3 << "," << p.force.feed_per_tooth_m * 1e3 << ","
       << p.force.engaged_angle_rad * kDeg << "," << p.force.feed_force_N << "," << p.force.normal_force_N << ","
       << p.force.mean_resultant_N << "," << p.force.peak_resultant_N << "," << p.force.peak_tooth_N << ","
       << p.force.peak_normal_N << "," << (p.binding ? process::to_string(*p.binding) : "") << "\n";
  return os.str();
}

plot::Figure process_figure(const ProcessRun& r) {
  plot::Figure fig = plot::figure(1000, 900);
  fig.rows = 2;
  plot::Panel f = plot::panel("Milling force along the path", "arc length (mm)", "force (N)");
  plot::Panel v = plot::panel("Feed", "arc length (mm)", "feed (mm/s)");
  plot::Series mean, peak, feed;
  mean.label = "mean force";
  peak.label = "peak force";
  peak.color = plot::palette(1);
  peak.dashed = true;
  feed.label = r.constant_force ? "constant-force feed" : "job's feed";
  for (const ProcessPoint& p : r.points) {
    mean.x.push_back(p.s * 1e3);
    mean.y.push_back(p.force.mean_resultant_N);
    peak.x.push_back(p.s * 1e3);
    peak.y.push_back(p.force.peak_resultant_N);
    feed.x.push_back(p.s * 1e3);
    feed.y.push_back(p.v * 1e3);
  }
  f.series.push_back(std::move(mean));
  f.series.push_back(std::move(peak));
  if (r.limits) f.hlines.push_back(r.limits->nominal_force_N);
  f.ymin = 0.0;
  v.series.push_back(std::move(feed));
  v.ymin = 0.0;
  fig.panels.push_back(std::move(f));
  fig.panels.push_back(std::move(v));
  return fig;
}

}  // namespace polarcam
