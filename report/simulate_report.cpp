#include "report/simulate_report.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "cam/format.hpp"
#include "report/report_numbers.hpp"

namespace polarcam {
namespace {

constexpr double kMmPerMin = 1e3 * 60.0;          // m/s to mm/min
constexpr double kInPerMin = 60.0 / 0.0254;       // m/s to in/min
constexpr double kIn = 1.0 / 0.0254;              // m to in
constexpr double kLbf = 1.0 / 4.4482216152605;    // N to lbf
constexpr double kMm = 1e3;

using report_numbers::optional_number;

const char* action_name(process::BandAction a) {
  switch (a) {
    case process::BandAction::decrease: return "decrease";
    case process::BandAction::hold: return "hold";
    case process::BandAction::increase: return "increase";
  }
  return "hold";
}

double band_scale(process::BandQuantity q) { return q == process::BandQuantity::feed_per_tooth ? kIn : kLbf; }
const char* band_unit(process::BandQuantity q) { return q == process::BandQuantity::feed_per_tooth ? "in" : "lbf"; }

}  // namespace

nlohmann::ordered_json ac_json(const AcReport& r) {
  const process::AcLoopSettings& s = r.problem.settings;
  const process::AcResult& a = r.result;
  nlohmann::ordered_json j;
  j["model"] = "Elbestawi 1980 A/C loop";
  j["strategy"] = process::strategy_name(s.strategy);
  j["dda_rate_hz"] = s.dda_rate_hz;
  j["control_period_s"] = s.control_period_s;
  j["K_ac_mm_per_s2"] = s.K_ac * kMm;
  j["B_mm_per_s"] = s.B * kMm;
  j["F_nom_N"] = s.F_nom;
  j["tooth_period_s"] = a.tooth_period_s;
  j["cutting_stiffness_N_per_mm"] = s.cutting_stiffness / kMm;
  j["cutting_rate_N_per_mm_per_s"] = s.cutting_stiffness * a.tooth_period_s / kMm;
  j["spindle_stiffness_N_per_mm"] = s.spindle_stiffness ? nlohmann::ordered_json(*s.spindle_stiffness / kMm)
                                                          : nlohmann::ordered_json();
  j["impact_time_s"] = optional_number(a.impact_time_s);
  j["peak_force_N"] = a.peak_force;
  j["peak_force_time_s"] = a.peak_force_time_s;
  j["final_feed_mm_per_min"] = a.final_feed * kMmPerMin;
  j["final_force_N"] = a.final_force;
  j["steady_feed_mm_per_min"] = process::ac_steady_feed(s) * kMmPerMin;
  j["command_limited_samples"] = a.command_limited_samples;
  j["force_limit_N"] = optional_number(r.problem.force_limit);
  j["limit_exceeded"] = r.limit_exceeded;
  if (!r.poles.empty()) {
    nlohmann::ordered_json p = nlohmann::ordered_json::array();
    for (const auto& z : r.poles) p.push_back({{"re", z.real()}, {"im", z.imag()}});
    j["eq5_21"] = {{"poles", p}, {"dominant_damping", optional_number(process::dominant_damping(r.poles))}};
  }
  return j;
}

std::string ac_text(const AcReport& r) {
  const process::AcLoopSettings& s = r.problem.settings;
  const process::AcResult& a = r.result;
  std::ostringstream os;
  os << "A/C loop (Elbestawi 1980), strategy " << process::strategy_name(s.strategy) << ": F_nom "
     << significant(s.F_nom, 6) << " N, K_ac " << significant(s.K_ac * kMm, 6) << " mm/s^2, B "
     << significant(s.B * kMm, 6) << " mm/s, " << significant(s.dda_rate_hz, 6) << " Hz DDA\n";
  if (s.strategy == process::ImpactStrategy::none)  // no impact is watched for: the law runs from the first sample
    os << "  no impact strategy; peak force " << significant(a.peak_force, 6) << " N at "
       << significant(a.peak_force_time_s, 6) << " s\n";
  else if (a.impact_time_s)
    os << "  impact at " << significant(*a.impact_time_s, 6) << " s; peak force " << significant(a.peak_force, 6)
       << " N at " << significant(a.peak_force_time_s, 6) << " s\n";
  else
    os << "  no impact: the force never exceeded " << significant(s.impact_threshold, 6) << " N\n";
  os << "  at the end: feed " << significant(a.final_feed * kMmPerMin, 6) << " mm/min, force "
     << significant(a.final_force, 6) << " N (steady state of the law: " << significant(process::ac_steady_feed(s) * kMmPerMin, 6)
     << " mm/min)\n";
  if (a.command_limited_samples > 0)
    os << "  the command was held at 0 or the rapid feed at " << a.command_limited_samples << " control samples\n";
  if (!r.poles.empty()) {
    os << "  Eq. 5.21 closed-loop poles:";
    for (const auto& z : r.poles)
      os << " " << significant(z.real(), 6) << (z.imag() < 0 ? " - j" : " + j") << significant(std::abs(z.imag()), 6);
    if (auto d = process::dominant_damping(r.poles)) os << "; dominant damping " << significant(*d, 4);
    os << "\n";
  }
  if (r.problem.force_limit)
    os << "  force limit " << significant(*r.problem.force_limit, 6) << " N: "
       << (r.limit_exceeded ? "EXCEEDED" : "not exceeded") << "\n";
  return os.str();
}

std::string ac_csv(const process::AcResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "t_s,feed_mm_per_min,force_N,command_mm_per_min\n";
  for (const process::AcSample& s : r.series)
    os << s.t << "," << s.feed * kMmPerMin << "," << s.force << "," << s.command * kMmPerMin << "\n";
  return os.str();
}

plot::Figure ac_figure(const AcReport& r) {
  plot::Figure fig = plot::figure(1000, 900);
  fig.rows = 2;
  plot::Panel f = plot::panel(std::string("Adaptive control, strategy ") + process::strategy_name(r.problem.settings.strategy) +
                                  " (Elbestawi 1980, Sec. 5.4-5.8)",
                              "time (s)", "cutting force (N)");
  plot::Panel v = plot::panel("Feed", "time (s)", "feed (mm/min)");
  plot::Series force, feed, command;
  force.label = "force";
  feed.label = "table feed";
  command.label = "command V_com";
  command.color = plot::palette(1);
  command.dashed = true;
  // at most about 4000 points a line: every n-th interrupt
  const size_t every = std::max<size_t>(1, r.result.series.size() / 4000);
  for (size_t i = 0; i < r.result.series.size(); i += every) {
    const process::AcSample& s = r.result.series[i];
    force.x.push_back(s.t);
    force.y.push_back(s.force);
    feed.x.push_back(s.t);
    feed.y.push_back(s.feed * kMmPerMin);
    command.x.push_back(s.t);
    command.y.push_back(s.command * kMmPerMin);
  }
  f.series.push_back(std::move(force));
  f.hlines.push_back(r.problem.settings.F_nom);
  if (r.problem.force_limit) f.hlines.push_back(*r.problem.force_limit);
  f.ymin = 0.0;
  v.series.push_back(std::move(feed));
  v.series.push_back(std::move(command));
  v.ymin = 0.0;
  fig.panels.push_back(std::move(f));
  fig.panels.push_back(std::move(v));
  return fig;
}

nlohmann::ordered_json band_json(const BandReport& r) {
  const process::BandSettings& s = r.problem.settings;
  const process::BandResult& a = r.result;
  nlohmann::ordered_json j;
  j["model"] = "Fussell & Gagne 1991 band controller";
  j["rate_hz"] = s.rate_hz;
  j["step_fraction"] = s.step_fraction;
  j["programmed_feed_in_per_min"] = s.programmed_feed * kInPerMin;
  j["effective_gain_in_per_min_per_s"] = a.effective_gain * kInPerMin;
  nlohmann::ordered_json bands = nlohmann::ordered_json::array();
  for (const process::Band& b : s.bands) {
    const double k = band_scale(b.quantity);
    nlohmann::ordered_json o{{"event", b.event},
                             {"quantity", process::band_quantity_name(b.quantity)},
                             {"unit", band_unit(b.quantity)},
                             {"lower", b.lower * k},
                             {"upper", b.upper * k},
                             {"hard_limit", b.hard_limit ? nlohmann::ordered_json(*b.hard_limit * k) : nlohmann::ordered_json()}};
    if (b.quantity == process::BandQuantity::feed_per_tooth) {
      o["lower_feed_in_per_min"] = process::feed_for_feed_per_tooth(b.lower, s.cut.teeth, s.cut.spindle_speed_rad_s) * kInPerMin;
      o["upper_feed_in_per_min"] = process::feed_for_feed_per_tooth(b.upper, s.cut.teeth, s.cut.spindle_speed_rad_s) * kInPerMin;
    }
    bands.push_back(o);
  }
  j["bands"] = bands;
  j["settled_feed_before_step_in_per_min"] =
      a.settled_feed_before_step ? nlohmann::ordered_json(*a.settled_feed_before_step * kInPerMin) : nlohmann::ordered_json();
  const process::BandSample& end = a.series.back();
  j["final"] = {{"feed_in_per_min", end.feed * kInPerMin},
                {"command_in_per_min", end.command * kInPerMin},
                {"total_force_lbf", end.total_force * kLbf},
                {"perpendicular_force_lbf", end.perpendicular_force * kLbf},
                {"feed_per_tooth_in", end.feed_per_tooth * kIn},
                {"action", action_name(end.action)},
                {"event", end.active_event >= 0 ? nlohmann::ordered_json(s.bands[static_cast<size_t>(end.active_event)].event)
                                                : nlohmann::ordered_json()}};
  j["limit_cycle"] = a.limit_cycle;
  j["reversals_in_window"] = a.reversals;
  j["window_s"] = a.window_s;
  j["window_command_in_per_min"] = {a.cycle_feed_min * kInPerMin, a.cycle_feed_max * kInPerMin};
  j["peak_total_force_lbf"] = a.peak_total_force * kLbf;
  j["peak_perpendicular_force_lbf"] = a.peak_perpendicular_force * kLbf;
  j["peak_feed_per_tooth_in"] = a.peak_feed_per_tooth * kIn;
  j["override_limited_samples"] = a.override_limited_samples;
  j["exceeded"] = a.exceeded;
  j["limit_exceeded"] = r.limit_exceeded;
  return j;
}

std::string band_text(const BandReport& r) {
  const process::BandSettings& s = r.problem.settings;
  const process::BandResult& a = r.result;
  std::ostringstream os;
  os << "band controller (Fussell & Gagne 1991): " << significant(s.rate_hz, 6) << " Hz, steps of "
     << significant(s.step_fraction * 100, 4) << " % of " << significant(s.programmed_feed * kInPerMin, 6)
     << " in/min, effective gain " << significant(a.effective_gain * kInPerMin, 6) << " (in/min)/s\n";
  for (const process::Band& b : s.bands)
    os << "  " << b.event << ": " << process::band_quantity_name(b.quantity) << " " << significant(b.lower * band_scale(b.quantity), 6)
       << " to " << significant(b.upper * band_scale(b.quantity), 6) << " " << band_unit(b.quantity) << "\n";
  if (a.settled_feed_before_step)
    os << "  settled feed" << (s.cut.step_time ? " before the depth step: " : ": ")
       << significant(*a.settled_feed_before_step * kInPerMin, 6) << " in/min\n";
  const process::BandSample& end = a.series.back();
  os << "  at the end: command " << significant(end.command * kInPerMin, 6) << " in/min, total force "
     << significant(end.total_force * kLbf, 6) << " lbf, perpendicular " << significant(end.perpendicular_force * kLbf, 6)
     << " lbf, feed per tooth " << significant(end.feed_per_tooth * kIn, 6) << " in (" << action_name(end.action) << ")\n";
  if (a.limit_cycle)
    os << "  LIMIT CYCLE: " << a.reversals << " reversals in the last " << significant(a.window_s, 3)
       << " s, the command between " << significant(a.cycle_feed_min * kInPerMin, 6) << " and "
       << significant(a.cycle_feed_max * kInPerMin, 6) << " in/min\n";
  else
    os << "  no limit cycle\n";
  if (a.override_limited_samples > 0)
    os << "  the override was held at 0 or its maximum at " << a.override_limited_samples << " periods\n";
  for (const std::string& e : a.exceeded) os << "  EXCEEDED the tool's limit: " << e << "\n";
  return os.str();
}

std::string band_csv(const BandReport& r) {
  std::ostringstream os;
  os.precision(12);
  os << "t_s,feed_in_per_min,command_in_per_min,feed_per_tooth_in,total_force_lbf,perpendicular_force_lbf,action,event\n";
  for (const process::BandSample& s : r.result.series) {
    os << s.t << "," << s.feed * kInPerMin << "," << s.command * kInPerMin << "," << s.feed_per_tooth * kIn << ","
       << s.total_force * kLbf << "," << s.perpendicular_force * kLbf << "," << action_name(s.action) << ",";
    if (s.active_event >= 0) os << '"' << r.problem.settings.bands[static_cast<size_t>(s.active_event)].event << '"';
    os << "\n";
  }
  return os.str();
}

plot::Figure band_figure(const BandReport& r) {
  const process::BandSettings& s = r.problem.settings;
  plot::Figure fig = plot::figure(1000, 900);
  fig.rows = 2;
  plot::Panel f = plot::panel("Band controller: forces (Fussell & Gagne 1991, Sec. V-VI)", "time (s)", "force (lbf)");
  plot::Panel v = plot::panel("Feed", "time (s)", "feed (in/min)");
  plot::Series total, perp, feed, command;
  total.label = "total force";
  perp.label = "perpendicular force";
  perp.color = plot::palette(1);
  feed.label = "table feed";
  command.label = "command";
  command.color = plot::palette(1);
  command.dashed = true;
  for (const process::BandSample& x : r.result.series) {
    total.x.push_back(x.t);
    total.y.push_back(x.total_force * kLbf);
    perp.x.push_back(x.t);
    perp.y.push_back(x.perpendicular_force * kLbf);
    feed.x.push_back(x.t);
    feed.y.push_back(x.feed * kInPerMin);
    command.x.push_back(x.t);
    command.y.push_back(x.command * kInPerMin);
  }
  f.series.push_back(std::move(total));
  f.series.push_back(std::move(perp));
  v.series.push_back(std::move(feed));
  v.series.push_back(std::move(command));
  for (const process::Band& b : s.bands) {
    if (b.quantity == process::BandQuantity::feed_per_tooth) {
      v.hlines.push_back(process::feed_for_feed_per_tooth(b.lower, s.cut.teeth, s.cut.spindle_speed_rad_s) * kInPerMin);
      v.hlines.push_back(process::feed_for_feed_per_tooth(b.upper, s.cut.teeth, s.cut.spindle_speed_rad_s) * kInPerMin);
    } else {
      f.hlines.push_back(b.lower * kLbf);
      f.hlines.push_back(b.upper * kLbf);
    }
  }
  f.ymin = 0.0;
  v.ymin = 0.0;
  fig.panels.push_back(std::move(f));
  fig.panels.push_back(std::move(v));
  return fig;
}

}  // namespace polarcam
