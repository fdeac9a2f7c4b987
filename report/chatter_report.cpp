#include "report/chatter_report.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "cam/format.hpp"
#include "report/report_numbers.hpp"

namespace polarcam {
namespace {

constexpr double kRpm = 60.0;  // rev/s to rev/min

using report_numbers::optional_number;

}  // namespace

plot::Figure chatter_lobes_figure(const ChatterAnalysis& a) {
  plot::Figure fig = plot::figure(1000, 700);
  plot::Panel p = plot::panel("Regenerative chatter: stability lobes (Dunckley 1978, Sec. 2.2.4)",
                              "spindle speed (rev/min)", "limiting cutting gain K_c (N/m)");
  plot::Series s;
  s.label = "Nyquist limit: stable below";
  double lo = std::numeric_limits<double>::infinity();
  for (const process::LobePoint& l : a.lobes) {
    if (!l.limit.critical_gain) continue;
    s.x.push_back(l.spindle_speed * kRpm);
    s.y.push_back(*l.limit.critical_gain);
    lo = std::min(lo, *l.limit.critical_gain);
  }
  p.series.push_back(std::move(s));
  if (a.simple.gain) {
    plot::Series h;
    h.label = "simple criterion (any speed)";
    h.color = plot::palette(5);
    h.dashed = true;
    if (!a.lobes.empty()) {
      h.x = {a.lobes.front().spindle_speed * kRpm, a.lobes.back().spindle_speed * kRpm};
      h.y = {*a.simple.gain, *a.simple.gain};
    }
    p.series.push_back(std::move(h));
    lo = std::min(lo, *a.simple.gain);
  }
  if (a.nyquist.critical_gain) {
    p.series.push_back(plot::marker(kRpm / a.problem.cut.revolution_period, *a.nyquist.critical_gain,
                                    "this cut: K_c = " + significant(*a.nyquist.critical_gain, 4) + " N/m", 1, 4));
  }
  p.ymin = 0.0;
  if (std::isfinite(lo)) p.ymax = 8.0 * lo;  // the lobes' valleys; the peaks between them run off the top
  p.legend = plot::Panel::Legend::top_left;
  fig.panels.push_back(std::move(p));
  return fig;
}

nlohmann::ordered_json chatter_json(const ChatterAnalysis& a) {
  const auto& st = a.problem.structure;
  const auto& cut = a.problem.cut;
  nlohmann::ordered_json j;
  j["structure"] = {{"M_m_kg", st.M_m}, {"C_m_N_s_per_m", st.C_m}, {"K_m_N_per_m", st.K_m},
                    {"M_w_kg", st.M_w}, {"C_w_N_s_per_m", st.C_w}, {"K_w_N_per_m", st.K_w}};
  j["cut"] = {{"overlap", cut.overlap},
              {"revolution_period_s", cut.revolution_period},
              {"spindle_speed_rpm", kRpm / cut.revolution_period}};
  j["modes"] = nlohmann::ordered_json::array();
  for (const process::Mode& m : a.modes)
    j["modes"].push_back({{"omega_n_rad_s", m.omega_n}, {"zeta", m.zeta}, {"omega_d_rad_s", m.omega_d}});
  j["critical_gain"] = optional_number(a.nyquist.critical_gain);
  j["chatter_frequency_rad_s"] = a.nyquist.critical_gain ? nlohmann::ordered_json(a.nyquist.chatter_frequency)
                                                         : nlohmann::ordered_json();
  j["gain_unit"] = "N/m";
  j["simple_criterion"] = {{"critical_gain", optional_number(a.simple.gain)},
                           {"frequency_rad_s", a.simple.frequency},
                           {"min_real_compliance_m_per_N", a.simple.min_real}};
  if (!a.lobes.empty()) {
    j["lobes"] = nlohmann::ordered_json::array();
    for (const process::LobePoint& l : a.lobes) {
      j["lobes"].push_back({{"spindle_speed_rpm", l.spindle_speed * kRpm},
                            {"revolution_period_s", 1.0 / l.spindle_speed},
                            {"critical_gain", optional_number(l.limit.critical_gain)},
                            {"chatter_frequency_rad_s", l.limit.critical_gain
                                                            ? nlohmann::ordered_json(l.limit.chatter_frequency)
                                                            : nlohmann::ordered_json()}});
    }
  }
  if (a.simulation) {
    const process::SimulationResult& r = *a.simulation;
    j["simulation"] = {{"cutting_gain", *a.simulated_gain},
                       {"step_s", r.step},
                       {"duration_s", r.samples.back().t},
                       {"revolutions", r.revolution_amplitude.size()},
                       {"growth_per_revolution", r.growth_per_revolution},
                       {"growing", r.growth_per_revolution > 1.0},
                       {"frequency_rad_s", r.frequency},
                       {"equilibrium_x_w_m", r.static_displacement},
                       {"last_revolution_amplitude_m",
                        r.revolution_amplitude.empty() ? 0.0 : r.revolution_amplitude.back()}};
  }
  if (a.suppression) {
    const process::SuppressionRun& r = *a.suppression;
    const process::SuppressorSpec& sp = *a.problem.suppressor;
    auto run = [](const process::SimulationResult& s) {
      return nlohmann::ordered_json{
          {"growth_per_revolution", s.growth_per_revolution},
          {"growing", s.growth_per_revolution > 1.0},
          {"last_revolution_amplitude_m", s.revolution_amplitude.empty() ? 0.0 : s.revolution_amplitude.back()},
          {"last_revolution_half_range_x_w_m", s.revolution_half_range.empty() ? 0.0 : s.revolution_half_range.back()},
          {"last_revolution_half_range_relative_m",
           s.revolution_relative_half_range.empty() ? 0.0 : s.revolution_relative_half_range.back()}};
    };
    const double without = r.without.revolution_half_range.empty() ? 0.0 : r.without.revolution_half_range.back();
    const double with = r.with.revolution_half_range.empty() ? 0.0 : r.with.revolution_half_range.back();
    j["suppressor"] = {
        {"cutting_gain", *a.simulated_gain},
        {"sample_period_s", sp.sample_period},
        {"step_size_m", sp.step_size},
        {"max_step_rate_per_s", sp.max_step_rate},
        {"max_steps_per_period", r.steps_per_period_limit},
        {"model",
         {{"source", process::to_string(sp.source)},
          {"frequency_scale", sp.model_frequency_scale},
          {"omega_n_rad_s", r.model.omega_n},
          {"zeta", r.model.zeta},
          {"gain_m_per_N", r.model.gain},
          {"A1", r.model.A1},
          {"A2", r.model.A2},
          {"B1", r.model.B1},
          {"B2", r.model.B2}}},
        {"without", run(r.without)},
        {"with", run(r.with)},
        {"amplitude_reduction", with > 0.0 ? nlohmann::ordered_json(without / with) : nlohmann::ordered_json()},
        {"steps_issued", r.steps_forward + r.steps_reverse},
        {"steps_forward", r.steps_forward},
        {"steps_reverse", r.steps_reverse},
        {"final_position_steps", r.final_position},
        {"sample_periods", r.periods},
        {"max_steps_in_period", r.max_steps_in_period},
        {"max_step_rate_used_per_s", r.max_step_rate_used},
        {"saturated", r.saturated_periods > 0},
        {"saturated_periods", r.saturated_periods},
        {"first_saturation_s", r.first_saturation ? nlohmann::ordered_json(*r.first_saturation) : nlohmann::ordered_json()},
        {"max_shortfall_steps", r.max_shortfall}};
  }
  return j;
}

std::string chatter_text(const ChatterAnalysis& a) {
  std::ostringstream os;
  const auto& cut = a.problem.cut;
  os << "regenerative chatter (Dunckley 1978): overlap " << significant(cut.overlap, 4) << ", revolution period "
     << significant(cut.revolution_period, 6) << " s (" << significant(60.0 / cut.revolution_period, 6) << " rpm)\n";
  for (size_t i = 0; i < a.modes.size(); ++i)
    os << "  mode " << i + 1 << ": " << significant(a.modes[i].omega_n, 6) << " rad/s, zeta "
       << significant(a.modes[i].zeta, 4) << "\n";
  if (a.nyquist.critical_gain)
    os << "  Nyquist: stable for K_c below " << significant(*a.nyquist.critical_gain, 6) << " N/m; chatter at "
       << significant(a.nyquist.chatter_frequency, 6) << " rad/s\n";
  else
    os << "  Nyquist: no limit (the open loop never crosses the negative real axis)\n";
  if (a.simple.gain)
    os << "  simple criterion (any revolution period): stable for K_c below " << significant(*a.simple.gain, 6)
       << " N/m (Re G is least, " << significant(a.simple.min_real, 4) << " m/N, at "
       << significant(a.simple.frequency, 6) << " rad/s)\n";
  if (!a.lobes.empty()) {
    os << "  spindle_rpm  critical_gain_N_per_m  chatter_rad_s\n";
    for (const process::LobePoint& l : a.lobes) {
      char b[128];
      if (l.limit.critical_gain)
        std::snprintf(b, sizeof b, "  %11.4f  %21.6g  %13.6g\n", l.spindle_speed * 60.0, *l.limit.critical_gain,
                      l.limit.chatter_frequency);
      else
        std::snprintf(b, sizeof b, "  %11.4f  %21s  %13s\n", l.spindle_speed * 60.0, "none", "-");
      os << b;
    }
  }
  if (a.simulation) {
    const auto& r = *a.simulation;
    os << "  simulated at K_c = " << significant(*a.simulated_gain, 6) << " N/m for " << r.revolution_amplitude.size()
       << " revolutions: the vibration " << (r.growth_per_revolution > 1.0 ? "grows" : "decays") << " by a factor "
       << significant(r.growth_per_revolution, 6) << " per revolution at " << significant(r.frequency, 6)
       << " rad/s\n";
  }
  if (a.suppression) {
    const auto& r = *a.suppression;
    const auto& sp = *a.problem.suppressor;
    auto last = [](const std::vector<double>& v) { return v.empty() ? 0.0 : v.back(); };
    os << "  suppressor: model " << process::to_string(sp.source) << " (" << significant(r.model.omega_n, 6)
       << " rad/s, zeta " << significant(r.model.zeta, 4) << ", " << significant(r.model.gain, 4)
       << " m/N), sample period " << significant(sp.sample_period, 6) << " s, step " << significant(sp.step_size, 6)
       << " m\n";
    os << "    last revolution: X_w half range " << significant(last(r.without.revolution_half_range), 4)
       << " m without, " << significant(last(r.with.revolution_half_range), 4) << " m with; growth per revolution "
       << significant(r.without.growth_per_revolution, 5) << " without, " << significant(r.with.growth_per_revolution, 5)
       << " with\n";
    os << "    " << r.steps_forward + r.steps_reverse << " steps (" << r.steps_forward << " forward, " << r.steps_reverse
       << " reverse), final position " << r.final_position << ", largest rate " << significant(r.max_step_rate_used, 6)
       << " steps/s";
    if (r.saturated_periods > 0)
      os << "; SATURATED in " << r.saturated_periods << " of " << r.periods << " periods, first at "
         << significant(*r.first_saturation, 6) << " s";
    os << "\n";
  }
  return os.str();
}

std::string simulation_csv(const process::SimulationResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "t_s,x_m_m,x_w_m,force_N\n";
  for (const process::SimulationSample& s : r.samples) os << s.t << "," << s.x_m << "," << s.x_w << "," << s.force << "\n";
  return os.str();
}

std::string suppression_csv(const process::SimulationResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "t_s,x_m_m,x_w_m,x_t_m,force_N\n";
  for (const process::SimulationSample& s : r.samples)
    os << s.t << "," << s.x_m << "," << s.x_w << "," << s.x_t << "," << s.force << "\n";
  return os.str();
}

std::string steps_csv(const process::SuppressionRun& r) {
  std::string out = "t_s,dir,position_steps\n";
  char b[96];
  for (const process::PositionerStep& s : r.steps) {
    std::snprintf(b, sizeof b, "%.12f,%d,%lld\n", s.t, s.dir, s.position);
    out += b;
  }
  return out;
}

}  // namespace polarcam
