#pragma once
// Rendering the process-control simulations of `polarcam simulate` (process/ac_loop.hpp, band_control.hpp):
// JSON and text summaries, the time series as CSV, the figures (PLplot). Nothing here computes a number of the
// simulation.
#include <complex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "process/sim_file.hpp"
#include "report/plot.hpp"

namespace polarcam {

struct AcReport {
  process::AcProblem problem;
  process::AcResult result;
  std::vector<std::complex<double>> poles;  // Eq. 5.21, empty for a rigid spindle
  bool limit_exceeded = false;
};

struct BandReport {
  process::BandProblem problem;
  process::BandResult result;
  bool limit_exceeded = false;
};

nlohmann::ordered_json ac_json(const AcReport& r);
std::string ac_text(const AcReport& r);
// t_s,feed_mm_per_min,force_N,command_mm_per_min: one row per DDA interrupt.
std::string ac_csv(const process::AcResult& r);
// Two panels over time: the force with F_nom; the table's feed and the command.
plot::Figure ac_figure(const AcReport& r);

nlohmann::ordered_json band_json(const BandReport& r);
std::string band_text(const BandReport& r);
// t_s,feed_in_per_min,command_in_per_min,feed_per_tooth_in,total_force_lbf,perpendicular_force_lbf,action,event:
// one row per controller period, in the report's units.
std::string band_csv(const BandReport& r);
// Two panels over time: the sensed forces with their bands; the feed and the command with the tooth band's feeds.
plot::Figure band_figure(const BandReport& r);

}  // namespace polarcam
