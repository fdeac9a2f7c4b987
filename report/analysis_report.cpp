#include "report/analysis_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>

#include "report/report_numbers.hpp"

namespace polarcam::cli {
namespace {

using json = nlohmann::ordered_json;

using report_numbers::g;

// JSON numbers are finite; an infinite ratio (no pull-out torque left) is null.
using report_numbers::num;

Vec2 contour_point(const Job& job, const TorqueSample& x) {
  return Vec2{x.r * std::cos(x.theta), x.r * std::sin(x.theta)} + job.placement.pole();
}

json place_json(const Job& job, const TorqueSample& x) {
  const Vec2 p = contour_point(job, x);
  return {{"theta_rad", x.theta}, {"r_m", x.r}, {"s_m", x.s}, {"t_s", x.t}, {"point_m", {p.x, p.y}}};
}

using report_numbers::axis_name;

json axis_json(const AxisExtremes& e, const AxisVerdict& v, const StepperMotor& motor,
               const AxisDemand TorqueSample::*d, const Job& job) {
  const TorqueSample& at = e.ratio.at;
  json j;
  j["max_torque_ratio"] = num(e.ratio.value);
  j["theta_at_max_rad"] = at.theta;
  j["r_at_max_m"] = at.r;
  j["s_at_max_m"] = at.s;
  j["t_at_max_s"] = at.t;
  const Vec2 p = contour_point(job, at);
  j["point_at_max_m"] = {p.x, p.y};
  j["torque_at_max_Nm"] = (at.*d).torque;
  j["pullout_at_max_Nm"] = (at.*d).pullout;
  j["step_rate_at_max_hz"] = (at.*d).step_rate;
  j["max_torque_Nm"] = e.torque.value;
  j["theta_at_max_torque_rad"] = e.torque.at.theta;
  j["max_step_rate_hz"] = e.step_rate.value;
  j["theta_at_max_step_rate_rad"] = e.step_rate.at.theta;
  j["step_rate_limit_hz"] = motor.max_step_rate ? json(*motor.max_step_rate) : json(nullptr);
  j["margin"] = num(v.margin);
  j["failure"] = v.failure == Failure::none ? json(nullptr) : json(to_string(v.failure));
  j["motor"] = motor.describe();
  return j;
}

json load_json(const CaseResult& c) {
  const LoadSpec& l = c.spec.load;
  json j;
  j["kind"] = to_string(l.kind);
  j["added_mass_kg"] = l.mass;
  if (l.kind == LoadKind::grinding) {
    j["k_c_Npm2"] = l.grinding.k_c;
    j["c1"] = l.grinding.c1;
    j["depth_m"] = l.grinding.depth;
    j["width_m"] = l.grinding.width;
    j["wheel_speed_mps"] = l.grinding.wheel_speed;
    j["K_c_Nspm"] = l.grinding.K_c();
  }
  if (l.kind == LoadKind::milling) {
    j["spindle_speed_rad_s"] = l.milling.spindle_speed;
    j["axial_depth_m"] = l.milling.axial_depth;
    j["radial_width_m"] = l.milling.radial_width;
  }
  if (c.speed) {
    const ToolForce f = c.load.force(0.0, *c.speed);
    j["force_tangential_N"] = f.tangential;
    j["force_normal_N"] = f.normal;
  }
  return j;
}

std::string mm(double m) { return g(m * 1e3, 4) + " mm"; }
std::string cms(double v) { return g(v * 1e2, 4) + " cm/s"; }

std::string load_text(const CaseResult& c) {
  const LoadSpec& l = c.spec.load;
  std::string s = to_string(l.kind);
  if (l.mass > 0.0) s += ", " + g(l.mass) + " kg on the carriage";
  if (l.kind == LoadKind::grinding)
    s += ", depth " + mm(l.grinding.depth) + ", width " + mm(l.grinding.width) + ", K_c " + g(l.grinding.K_c()) +
         " N s/m";
  if (l.kind == LoadKind::milling)
    s += ", milling: axial depth " + mm(l.milling.axial_depth) + ", radial width " + mm(l.milling.radial_width);
  if ((l.kind == LoadKind::grinding || l.kind == LoadKind::force || l.kind == LoadKind::milling) && c.speed) {
    const ToolForce f = c.load.force(0.0, *c.speed);
    s += " (tool force " + g(f.tangential) + " N tangential, " + g(f.normal) + " N normal)";
  }
  return s;
}

std::string axis_text(const char* name, const AxisExtremes& e, const AxisDemand TorqueSample::*d,
                      const StepperMotor& m) {
  const TorqueSample& at = e.ratio.at;
  std::string s =
      fmt::format("  {:<10} max torque ratio {} at theta = {} rad, r = {}: needs {} N m, pull-out {} N m at {} Hz\n",
                  name, std::isfinite(e.ratio.value) ? g(e.ratio.value) : "inf (no pull-out torque)", g(at.theta),
                  mm(at.r), g(std::abs((at.*d).torque)), g((at.*d).pullout), g((at.*d).step_rate));
  s += fmt::format("  {:<10} max torque {} N m at theta = {} rad; max step rate {} Hz at theta = {} rad{}\n", "",
                   g(e.torque.value), g(e.torque.at.theta), g(e.step_rate.value), g(e.step_rate.at.theta),
                   m.max_step_rate ? " (limit " + g(*m.max_step_rate) + " Hz)" : "");
  return s;
}

}  // namespace

std::string case_label(const CaseResult& c) {
  std::string s = c.speed ? "V = " + cms(*c.speed) : (c.plan ? "time-optimal" : "speed table");
  const LoadSpec& l = c.spec.load;
  if (l.kind == LoadKind::inertial || l.mass > 0.0) s += ", M = " + g(l.mass) + " kg";
  if (l.kind == LoadKind::grinding) s += ", d = " + mm(l.grinding.depth);
  if (l.kind == LoadKind::force) s += ", F = " + g(l.force.tangential) + " N";
  if (l.kind == LoadKind::milling) s += ", milling b = " + mm(l.milling.axial_depth);
  return s;
}

std::string verdict_line(const Job& job, const CaseResult& c) {
  const Verdict& v = c.verdict;
  std::string s;
  if (v.go) {
    s = fmt::format("GO: every torque ratio within {} (safety factor {}); largest {} on the {} axis", g(v.limit),
                    g(v.safety_factor), g(std::max(v.radial.ratio, v.angular.ratio)),
                    v.radial.ratio >= v.angular.ratio ? "radial" : "angular");
  } else {
    const AxisVerdict& av = v.axis == 0 ? v.radial : v.angular;
    const TorqueSample& w = v.where;
    const Vec2 p = contour_point(job, w);
    const std::string place =
        fmt::format("theta = {} rad, r = {}, {} along the path (t = {} s), contour point ({}, {})", g(w.theta), mm(w.r),
                    mm(w.s), g(w.t), mm(p.x), mm(p.y));
    const AxisDemand& d = v.axis == 0 ? w.radial : w.angular;
    if (v.failure == Failure::step_rate) {
      s = fmt::format("NO-GO: the {} motor must step at {} Hz, above its limit of {} Hz, at {}", axis_name(v.axis),
                      g(d.step_rate), g(*av.rate_limit), place);
    } else if (v.failure == Failure::no_pullout) {
      s = fmt::format("NO-GO: the {} motor has no pull-out torque left at {} Hz, at {}", axis_name(v.axis),
                      g(d.step_rate), place);
    } else {
      s = fmt::format(
          "NO-GO: the {} axis needs {} times its motor's pull-out torque ({} of {} N m at {} Hz; limit {}, "
          "safety factor {}) at {}; short by {} %",
          axis_name(v.axis), g(av.ratio), g(std::abs(d.torque)), g(d.pullout), g(d.step_rate), g(v.limit),
          g(v.safety_factor), place, g(-100.0 * av.margin, 3));
    }
    // a step rate over its limit is named even when the torque is what fails first
    for (int axis = 0; axis < 2; ++axis) {
      const AxisVerdict& x = axis == 0 ? v.radial : v.angular;
      if (!x.rate_limit || !(x.rate_margin < 0.0) || (v.failure == Failure::step_rate && axis == v.axis)) continue;
      const AxisExtremes& e = axis == 0 ? c.analysis.radial : c.analysis.angular;
      s += fmt::format("; the {} motor must also step at {} Hz, above its limit of {} Hz (at theta = {} rad)",
                       axis_name(axis), g(e.step_rate.value), g(*x.rate_limit), g(e.step_rate.at.theta));
    }
  }
  if (c.search.factor && c.speed) {
    const double vp = *c.search.factor * *c.speed;
    if (v.go)
      s += fmt::format("; passes up to {}{}", cms(vp), c.search.capped ? " (or more)" : "");
    else
      s += fmt::format("; passes at {} or slower", cms(vp));
  } else if (c.search.factor && !v.go) {
    s += fmt::format("; passes with the speed table scaled by {}", g(*c.search.factor));
  } else if (!v.go && c.search.evaluations > 0) {
    s += "; no speed down to a thousandth of this one passes: reduce the load, or the speed further";
  }
  return s;
}

json speed_plan_json(const SpeedPlan& p) {
  json j;
  j["time_optimal_s"] = p.time();
  j["constant_speed_mps"] = p.constant_speed ? json(*p.constant_speed) : json(nullptr);
  j["constant_speed_capped"] = p.constant_capped;
  j["constant_time_s"] = num(p.constant_time);
  j["saving_s"] = num(p.saving());
  j["saving_percent"] = num(std::isfinite(p.constant_time) ? 100.0 * p.saving() / p.constant_time : p.constant_time);
  j["speed_cap_mps"] = p.speed_cap ? json(*p.speed_cap) : json(nullptr);
  double top = 0.0;
  for (const SpeedStation& st : p.schedule.stations) top = std::max(top, st.v);
  j["top_speed_mps"] = top;
  j["stations"] = p.schedule.stations.size();
  j["worst_torque_ratio"] = num(p.schedule.worst_ratio);
  j["check_rounds"] = p.schedule.rounds;
  j["stretches"] = json::array();
  for (const ScheduleStretch& st : p.schedule.stretches)
    j["stretches"].push_back({{"s0_m", st.s0}, {"s1_m", st.s1}, {"phase", to_string(st.phase)},
                              {"binding", to_string(st.binding)}});
  return j;
}

std::string speed_plan_text(const SpeedPlan& p) {
  std::string s;
  double top = 0.0;
  for (const SpeedStation& st : p.schedule.stations) top = std::max(top, st.v);
  s += fmt::format("  {:<10} time-optimal schedule: {} s, top speed {}, from rest to rest ({} stations)\n", "schedule",
                   g(p.time(), 6), cms(top), p.schedule.stations.size());
  if (p.constant_speed)
    s += fmt::format("  {:<10} {} s at the best constant speed {}{} (same safety factor): {} s saved ({} %)\n",
                     "constant", g(p.constant_time, 6), cms(*p.constant_speed),
                     p.constant_capped ? (p.speed_cap ? " (the job's speed)" : " (or more)") : "", g(p.saving(), 4),
                     g(100.0 * p.saving() / p.constant_time, 3));
  else
    s += fmt::format("  {:<10} no constant speed passes at this safety factor\n", "constant");
  // the binding constraints, by share of the path
  std::map<std::string, double> share;
  for (const ScheduleStretch& st : p.schedule.stretches)
    share[std::string(to_string(st.phase)) + ": " + to_string(st.binding)] += st.s1 - st.s0;
  std::vector<std::pair<double, std::string>> by(share.size());
  std::transform(share.begin(), share.end(), by.begin(), [](const auto& kv) { return std::pair{-kv.second, kv.first}; });
  std::sort(by.begin(), by.end());
  const double L = p.schedule.profile->length();
  std::string list;
  for (const auto& [len, what] : by) list += (list.empty() ? "" : "; ") + what + " " + g(-100.0 * len / L, 3) + " %";
  s += fmt::format("  {:<10} {}\n", "binding", list);
  return s;
}

std::string speed_plan_csv(const SpeedPlan& p) {
  const auto& st = p.schedule.stations;
  const SpeedProfile& prof = *p.schedule.profile;
  std::string out = "s_m,t_s,speed_mps,accel_mps2,phase,binding\n";
  auto it = std::back_inserter(out);
  size_t k = 0;
  const auto& stretches = p.schedule.stretches;
  for (size_t i = 0; i < st.size(); ++i) {
    while (k + 1 < stretches.size() && st[i].s >= stretches[k].s1) ++k;
    const double a = i + 1 < st.size() ? (st[i + 1].v * st[i + 1].v - st[i].v * st[i].v) / (2.0 * (st[i + 1].s - st[i].s)) : 0.0;
    const bool last = i + 1 == st.size() || stretches.empty();
    fmt::format_to(it, "{:.10g},{:.10g},{:.10g},{:.10g},{},{}\n", st[i].s, prof.time_at(st[i].s), st[i].v, a,
                   last ? "end" : to_string(stretches[k].phase), last ? "rest" : to_string(stretches[k].binding));
  }
  return out;
}

json case_json(const Job& job, const CaseResult& c) {
  const MachineModel& m = *job.machine.dynamics;
  const TorqueAnalysis& a = c.analysis;
  const Verdict& v = c.verdict;
  json j;
  j["speed_mps"] = c.speed ? json(*c.speed) : json(nullptr);
  j["load"] = load_json(c);
  j["path_length_m"] = a.length;
  j["duration_s"] = a.duration;
  j["samples"] = a.samples;
  j["radial"] = axis_json(a.radial, v.radial, m.radial, &TorqueSample::radial, job);
  j["angular"] = axis_json(a.angular, v.angular, m.angular, &TorqueSample::angular, job);
  j["total"] = {{"max_torque_Nm", a.total_torque.value},
                {"theta_at_max_rad", a.total_torque.at.theta},
                {"s_at_max_m", a.total_torque.at.s},
                {"max_ratio_sum", num(a.ratio_sum.value)},
                {"theta_at_max_ratio_sum_rad", a.ratio_sum.at.theta}};
  j["verdict"] = v.go ? "GO" : "NO-GO";
  j["safety_factor"] = v.safety_factor;
  j["ratio_limit"] = v.limit;
  j["margin"] = num(std::min(v.radial.margin, v.angular.margin));
  j["failing_axis"] = v.go ? json(nullptr) : json(axis_name(v.axis));
  j["failure"] = v.go ? json(nullptr) : json(to_string(v.failure));
  j["where"] = v.go ? json(nullptr) : place_json(job, v.where);
  j["max_passing_speed_factor"] = c.search.factor ? json(*c.search.factor) : json(nullptr);
  j["max_passing_speed_mps"] = (c.search.factor && c.speed) ? json(*c.search.factor * *c.speed) : json(nullptr);
  j["max_passing_speed_capped"] = c.search.capped;
  j["corners"] = json::array();
  for (const Corner& k : a.corners)
    j["corners"].push_back({{"theta_rad", k.theta},
                            {"r_m", k.r},
                            {"s_m", k.s},
                            {"turn_rad", k.turn},
                            {"radial_step_rate_jump_hz", k.radial_rate_jump},
                            {"angular_step_rate_jump_hz", k.angular_rate_jump}});
  if (c.plan) j["time_optimal"] = speed_plan_json(*c.plan);
  j["message"] = verdict_line(job, c);
  return j;
}

std::string case_text(const Job& job, const CaseResult& c) {
  const MachineModel& m = *job.machine.dynamics;
  const TorqueAnalysis& a = c.analysis;
  std::string s;
  s += fmt::format("  {:<10} {}, load {}\n", "motion", c.speed ? cms(*c.speed) : (c.plan ? "time-optimal" : "speed table"),
                   load_text(c));
  if (c.plan) s += speed_plan_text(*c.plan);
  s += axis_text("radial", a.radial, &TorqueSample::radial, m.radial);
  s += axis_text("angular", a.angular, &TorqueSample::angular, m.angular);
  s += fmt::format("  {:<10} max |T_R| + |T_theta| = {} N m at theta = {} rad; max sum of ratios {}\n", "total",
                   g(a.total_torque.value), g(a.total_torque.at.theta), g(a.ratio_sum.value));
  s += fmt::format("  {:<10} {}\n", "verdict", verdict_line(job, c));
  if (!a.corners.empty()) {
    double jr = 0.0, jt = 0.0;
    for (const Corner& k : a.corners) jr = std::max(jr, k.radial_rate_jump), jt = std::max(jt, k.angular_rate_jump);
    s += fmt::format(
        "  {:<10} the path has {} corner{} where the axis speeds jump (up to {} Hz radial, {} Hz angular); the model "
        "assumes a smooth path and does not cover them\n",
        "warning", a.corners.size(), a.corners.size() == 1 ? "" : "s", g(jr), g(jt));
  }
  return s;
}

std::string series_csv(const Job& job, const std::vector<CaseResult>& cases) {
  const bool several = cases.size() > 1;
  std::string out;
  auto it = std::back_inserter(out);
  if (several) out += "case,";
  out +=
      "s_m,t_s,theta_rad,r_m,x_m,y_m,speed_mps,accel_mps2,gamma_rad,curvature_1pm,r_dot_mps,theta_dot_radps,"
      "r_ddot_mps2,theta_ddot_radps2,a_cr_mps2,a_cn_mps2,force_tangential_N,force_normal_N,torque_radial_Nm,"
      "torque_angular_Nm,step_rate_radial_hz,step_rate_angular_hz,pullout_radial_Nm,pullout_angular_Nm,"
      "ratio_radial,ratio_angular,total_torque_Nm\n";
  for (size_t k = 0; k < cases.size(); ++k) {
    for (const TorqueSample& x : cases[k].analysis.series) {
      const Vec2 p = contour_point(job, x);
      const SampleKinematics& st = x.st;
      if (several) fmt::format_to(it, "{},", k + 1);  // numbered from 1, as the text numbers them
      fmt::format_to(it, "{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},", x.s, x.t,
                     x.theta, x.r, p.x, p.y, st.V, st.a_t, st.gamma, st.kappa);
      fmt::format_to(it, "{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},", st.r_dot, st.theta_dot,
                     st.r_ddot, st.theta_ddot, st.a_cr, st.a_cn, x.force.tangential, x.force.normal);
      fmt::format_to(it, "{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g}\n", x.radial.torque,
                     x.angular.torque, x.radial.step_rate, x.angular.step_rate, x.radial.pullout, x.angular.pullout,
                     x.radial.ratio, x.angular.ratio, x.total_torque());
    }
  }
  return out;
}

namespace {

// At most about 2 * buckets points, keeping each bucket's lowest and highest value in path order, so that spikes
// survive.
void decimate(const std::vector<TorqueSample>& s, const AxisDemand TorqueSample::*axis, plot::Series& out,
              size_t buckets = 2500) {
  const size_t n = s.size();
  auto y = [&](size_t i) { return (s[i].*axis).ratio; };
  if (n <= 2 * buckets) {
    for (size_t i = 0; i < n; ++i) {
      out.x.push_back(s[i].theta);
      out.y.push_back(y(i));
    }
    return;
  }
  for (size_t b = 0; b < buckets; ++b) {
    const size_t i0 = b * n / buckets, i1 = (b + 1) * n / buckets;
    size_t lo = i0, hi = i0;
    for (size_t i = i0; i < i1; ++i) {
      if (y(i) < y(lo)) lo = i;
      if (y(i) > y(hi)) hi = i;
    }
    for (size_t i : {std::min(lo, hi), std::max(lo, hi)}) {
      out.x.push_back(s[i].theta);
      out.y.push_back(y(i));
    }
  }
}

std::string load_value_label(const CaseResult& c) {
  const LoadSpec& l = c.spec.load;
  if (l.kind == LoadKind::grinding) return "d = " + mm(l.grinding.depth);
  if (l.kind == LoadKind::force) return "F = " + g(l.force.tangential) + " N";
  return "M = " + g(l.mass) + " kg";
}

}  // namespace

plot::Figure torque_ratio_figure(const Job& job, const std::vector<CaseResult>& cases) {
  std::vector<double> speeds;
  std::vector<std::string> loads;
  for (const auto& c : cases) {
    const double v = c.speed.value_or(0.0);
    if (std::find(speeds.begin(), speeds.end(), v) == speeds.end()) speeds.push_back(v);
    const std::string l = load_value_label(c);
    if (std::find(loads.begin(), loads.end(), l) == loads.end()) loads.push_back(l);
  }
  const bool by_speed = speeds.size() > 1 && loads.size() > 1;
  const int cols = by_speed ? static_cast<int>(speeds.size()) : 1;
  plot::Figure f;
  f.cols = cols;
  f.rows = 2;
  f.width = 560 * cols + 240;
  f.height = 900;
  const double limit = cases.front().verdict.limit;
  for (int axis = 0; axis < 2; ++axis) {
    for (int col = 0; col < cols; ++col) {
      plot::Panel p;
      p.title = std::string(axis == 0 ? "Radial" : "Angular") + " axis torque ratio";
      if (by_speed) p.title += ", V = " + cms(speeds[static_cast<size_t>(col)]);
      p.xlabel = "theta (rad)  -  " + job.contour->name();
      p.ylabel = "torque ratio";
      double peak = 0.0;
      int colour = 0;
      for (const auto& c : cases) {
        if (by_speed && c.speed.value_or(0.0) != speeds[static_cast<size_t>(col)]) continue;
        plot::Series s;
        decimate(c.analysis.series, axis == 0 ? &TorqueSample::radial : &TorqueSample::angular, s);
        s.label = cases.size() == 1 ? "" : (by_speed ? load_value_label(c) : case_label(c));
        s.color = plot::palette(colour);
        s.width = 1.6;
        p.series.push_back(std::move(s));
        const Extreme& e = axis == 0 ? c.analysis.radial.ratio : c.analysis.angular.ratio;
        if (std::isfinite(e.value)) {
          plot::Series mk;
          mk.x = {e.at.theta};
          mk.y = {(axis == 0 ? e.at.radial : e.at.angular).ratio};
          mk.width = 0;
          mk.marker = 4;
          mk.marker_scale = 1.4;
          mk.color = plot::palette(colour);
          p.series.push_back(std::move(mk));
          peak = std::max(peak, e.value);
        }
        ++colour;
      }
      // the limit is drawn when the curves come near it; otherwise it would flatten them
      if (peak >= 0.25 * limit) p.hlines = {limit, -limit};
      // room above the curves for the legend (top right)
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& s : p.series)
        for (double y : s.y)
          if (std::isfinite(y)) lo = std::min(lo, y), hi = std::max(hi, y);
      for (double y : p.hlines) lo = std::min(lo, y), hi = std::max(hi, y);
      if (cases.size() > 1 && hi > lo) {
        p.ymin = lo - 0.04 * (hi - lo);
        const double share = 0.04 + 0.08 * static_cast<double>(colour);  // the legend's share of the height
        p.ymax = hi + 1.1 * share / (1.0 - share) * (hi - lo);
      }
      f.panels.push_back(std::move(p));
    }
  }
  return f;
}

}  // namespace polarcam::cli
