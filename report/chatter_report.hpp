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

}  // namespace polarcam
