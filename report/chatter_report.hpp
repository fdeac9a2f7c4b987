#pragma once
// Rendering the chatter analysis (process/): the stability lobes as a figure (PLplot) and the JSON of
// `polarcam chatter`, the simulated vibration as CSV. Nothing here computes a number of the analysis.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "process/chatter_file.hpp"
#include "process/simulate.hpp"
#include "process/stability.hpp"
#include "process/suppressor.hpp"
#include "report/plot.hpp"

namespace polarcam {

struct ChatterAnalysis {
  process::ChatterProblem problem;
  std::vector<process::Mode> modes;
  process::NyquistLimit nyquist;
  process::SimpleLimit simple;
  std::vector<process::LobePoint> lobes;            // empty unless asked
  std::optional<double> simulated_gain;             // --simulate
  std::optional<process::SimulationResult> simulation;
  std::optional<process::SuppressionRun> suppression;  // --suppress: the same cut with the stepper suppressor
};

// The stability lobes: the limiting K_c against spindle speed (rpm), the simple criterion's limit as a dashed line,
// the cut's own speed marked.
plot::Figure chatter_lobes_figure(const ChatterAnalysis& a);
// One JSON object: structure, cut, modes, critical_gain and chatter_frequency_rad_s (Nyquist), simple_criterion,
// lobes and simulation when present.
nlohmann::ordered_json chatter_json(const ChatterAnalysis& a);
// A text summary for the terminal.
std::string chatter_text(const ChatterAnalysis& a);
// t_s,x_m_m,x_w_m,force_N, one row per kept sample.
std::string simulation_csv(const process::SimulationResult& r);
// With the suppressor: t_s,x_m_m,x_w_m,x_t_m,force_N (x_t the tool's displacement), one row per kept sample.
std::string suppression_csv(const process::SimulationResult& r);
// The positioner's steps: t_s,dir,position_steps (the position after the step), one row per step, t_s to 1e-12 s.
std::string steps_csv(const process::SuppressionRun& r);

}  // namespace polarcam
