#include "report/capacity_report.hpp"

#include <fmt/format.h>

#include <cmath>

#include "cam/format.hpp"
#include "report/report_numbers.hpp"

namespace polarcam::cli {
namespace {

using json = nlohmann::ordered_json;

using report_numbers::g;
using report_numbers::num;

const char* load_key(LoadMeasure m) {
  switch (m) {
    case LoadMeasure::mass: return "max_mass_kg";
    case LoadMeasure::depth: return "max_depth_mm";
    case LoadMeasure::force: return "max_force_N";
    default: return "";
  }
}

}  // namespace

json capacity_json(const Job& job, const JobCapacity& c) {
  json j;
  j["job"] = job.file;
  j["safety_factor"] = job.safety_factor;
  j["ratio_limit"] = c.limit;
  j["speed_mps"] = c.speed ? json(*c.speed) : json(nullptr);
  const SpeedCapacity& s = c.speed_cap;
  j["max_speed_mps"] = s.factor ? json(*s.factor * c.top_speed) : json(nullptr);
  j["max_speed_factor"] = s.factor ? json(*s.factor) : json(nullptr);
  j["max_speed_capped"] = s.capped;
  j["worst_torque_ratio_at_max_speed"] = s.factor ? num(s.worst) : json(nullptr);
  j["max_speed_step_rate_mps"] = s.step_rate_factor ? json(*s.step_rate_factor * c.top_speed) : json(nullptr);
  const auto fu = usable_speed_factor(c);
  j["max_usable_speed_mps"] = fu ? json(*fu * c.top_speed) : json(nullptr);
  j["speed_limited_by"] = !fu                     ? json(nullptr)
                          : (s.step_rate_factor && *s.step_rate_factor < *s.factor) ? json("step_rate")
                                                                                    : json("torque");
  j["load_kind"] = to_string(job.load.kind);
  if (c.measure != LoadMeasure::none) {
    const LoadCapacity& l = c.load_cap;
    j["load_measure"] = to_string(c.measure);
    j["load_at_job"] = load_display(job, c.measure, c.load_at_job);
    j[load_key(c.measure)] = l.value ? json(load_display(job, c.measure, *l.value)) : json(nullptr);
    if (c.measure == LoadMeasure::force && l.value) {
      j["max_force_tangential_N"] = *l.value * job.load.force.tangential;
      j["max_force_normal_N"] = *l.value * job.load.force.normal;
    }
    j["load_capped"] = l.capped;
    const auto tf = theoretical_load_factor(job, c);
    j["load_theoretical_only"] = tf.has_value();
    j["worst_torque_ratio_at_max_load"] = l.value ? num(l.worst) : json(nullptr);
    j["load_at_speed_mps"] = c.load_speed;
  }
  if (!c.curve.empty()) {
    j["curve"] = json::array();
    for (const CapacityPoint& p : c.curve)
      j["curve"].push_back({{"speed_mps", p.speed},
                            {load_key(c.measure), p.load ? json(load_display(job, c.measure, *p.load)) : json(nullptr)},
                            {"capped", p.capped}});
  }
  j["evaluations"] = s.evaluations + c.load_cap.evaluations;
  return j;
}

std::string capacity_text(const Job& job, const JobCapacity& c) {
  std::string s = "polarcam capacity " + job.file + "\n";
  s += fmt::format("  limit      every torque ratio within {} (safety factor {})\n", g(c.limit), g(job.safety_factor));
  const SpeedCapacity& sc = c.speed_cap;
  const std::string at = c.speed ? g(*c.speed * 100) + " cm/s" : "the speed table";
  if (sc.factor)
    s += fmt::format("  speed      torque ratios reach the limit at {} cm/s{} (job: {}; worst ratio there {})\n",
                     g(*sc.factor * c.top_speed * 100, 6), sc.capped ? " or more (searched up to 100 times)" : "", at,
                     g(sc.worst, 6));
  else
    s += fmt::format("  speed      no speed down to a thousandth of the job's keeps the torque ratios within the limit\n");
  if (sc.step_rate_factor)
    s += fmt::format("             a motor reaches its maximum step rate at {} cm/s\n",
                     g(*sc.step_rate_factor * c.top_speed * 100, 6));
  if (c.measure != LoadMeasure::none) {
    const LoadCapacity& l = c.load_cap;
    const char* unit = load_display_unit(c.measure);
    if (l.value) {
      s += fmt::format("  load       largest {} at {} cm/s: {} {}{} (job: {} {}; worst ratio there {})\n",
                       load_display_name(c.measure), g(c.load_speed * 100), g(load_display(job, c.measure, *l.value), 6),
                       unit, l.capped ? " or more" : "", g(load_display(job, c.measure, c.load_at_job)), unit,
                       g(l.worst, 6));
      if (const auto tf = theoretical_load_factor(job, c))
        s += fmt::format("             a theoretical limit of the motors' torque only: {} times the carriage's own {} kg; "
                         "the arm, screw and bearings are not modelled, check what they can hold\n",
                         plain(*tf, 3), g(job.machine.dynamics->mech.carriage_mass, 3));
    } else
      s += fmt::format("  load       even without {} the torque ratios exceed the limit at {} cm/s\n",
                       load_display_name(c.measure), g(c.load_speed * 100));
    // the curve (--curve N, or for --csv and --plot): the largest load at each speed
    for (size_t i = 0; i < c.curve.size(); ++i) {
      const CapacityPoint& p = c.curve[i];
      s += fmt::format("  {}{} cm/s: {}\n", i == 0 ? "curve      " : "           ", g(p.speed * 100, 6),
                       p.load ? g(load_display(job, c.measure, *p.load), 6) + " " + unit + (p.capped ? " or more" : "")
                              : std::string("none within the limit"));
    }
  }
  return s;
}

std::string capacity_csv(const Job& job, const JobCapacity& c) {
  std::string out = fmt::format("speed_mps,{},capped\n", load_key(c.measure));
  for (const CapacityPoint& p : c.curve)
    out += fmt::format("{:.10g},{},{}\n", p.speed,
                       p.load ? fmt::format("{:.10g}", load_display(job, c.measure, *p.load)) : std::string(),
                       p.capped ? 1 : 0);
  return out;
}

plot::Figure capacity_figure(const Job& job, const JobCapacity& c) {
  plot::Figure f = plot::figure(1000, 620);
  plot::Panel p;
  const char* unit = load_display_unit(c.measure);
  p.title = std::string("Largest ") + load_display_name(c.measure) + " the drives carry, against speed";
  p.xlabel = "contouring speed (cm/s)";
  p.ylabel = std::string(load_display_name(c.measure)) + " (" + unit + ")";
  plot::Series cur;
  for (const CapacityPoint& q : c.curve)
    if (q.load) {
      cur.x.push_back(q.speed * 100);
      cur.y.push_back(load_display(job, c.measure, *q.load));
    }
  cur.label = "largest load within the torque limit";
  cur.color = plot::palette(0);
  cur.width = 2.0;
  cur.marker = 17;
  p.series.push_back(cur);
  const plot::Series jp =
      plot::marker(c.top_speed * 100, load_display(job, c.measure, c.load_at_job), "this job", 1, 4);
  p.series.push_back(jp);
  double ymax = 0.0;
  for (double y : cur.y) ymax = std::max(ymax, y);
  ymax = std::max(ymax, jp.y[0]);
  if (c.speed_cap.step_rate_factor) {
    plot::Series v;
    const double x = *c.speed_cap.step_rate_factor * c.top_speed * 100;
    v.x = {x, x};
    v.y = {0.0, ymax * 1.05};
    v.label = "step-rate limit";
    v.color = plot::palette(6);
    v.dashed = true;
    p.series.push_back(v);
  }
  p.ymin = 0.0;
  p.ymax = ymax * 1.3 + 1e-12;
  p.xmin = 0.0;
  f.panels.push_back(p);
  return f;
}

}  // namespace polarcam::cli
