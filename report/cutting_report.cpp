#include "report/cutting_report.hpp"

#include <fmt/format.h>

#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "report/process_report.hpp"
#include "report/report_numbers.hpp"

namespace polarcam {

namespace {
using report_numbers::g;
}  // namespace

void add_cutting_section(html::Report& rep, const Job& job, const ProcessRun& r) {
  const MillingLoadSpec& ml = job.load.milling;
  const MillingSetup& m = *r.setup;
  rep.heading(2, "Cutting", "cutting");
  rep.paragraph(fmt::format(
      "An end mill of {} mm, {} teeth, {} deg helix, milling {} at {} rev/min: axial depth {} mm, radial width {} mm, "
      "K_t {} N/mm^2, K_r {} N/mm^2. {}",
      g(m.tool.diameter_m * 1e3), m.tool.teeth, g(m.tool.helix_angle_rad * 180.0 / std::numbers::pi),
      to_string(r.mode), g(ml.spindle_speed * 60.0 / (2.0 * std::numbers::pi)), g(ml.axial_depth * 1e3),
      g(ml.radial_width * 1e3), g(ml.K_t * 1e-6), g(ml.K_r * 1e-6),
      r.limits ? fmt::format("The feed holds the mean cutting force at {} N where the limits allow it (top feed {} "
                             "mm/s): the path takes {} s.",
                             g(r.limits->nominal_force_N), g(r.limits->max_speed * 1e3), g(r.total_time_s))
               : fmt::format("At the job's own feed the path takes {} s.", g(r.total_time_s))));
  const process::ToolLimits& l = m.limits;
  std::vector<std::vector<std::string>> rows;
  auto row = [&](const char* what, double largest, std::optional<double> limit, const char* unit) {
    rows.push_back({what, g(largest) + " " + unit, limit ? g(*limit) + " " + unit : "-",
                    !limit ? "" : largest > *limit * (1.0 + 1e-9) ? "EXCEEDED" : "within"});
  };
  row("peak resultant force (breakage, Elbestawi Eq. 5.33)", r.max_peak_force_N, l.breakage_force_N, "N");
  row("peak resultant force (shank, Fussell & Gagne Eq. 7)", r.max_peak_force_N, l.shank_force_limit_N, "N");
  row("peak force on one tooth (Eq. 13)", r.max_tooth_force_N, l.tooth_force_limit_N, "N");
  row("peak force perpendicular to the feed (deflection, Eq. 21)", r.max_normal_force_N, l.deflection_force_limit_N,
      "N");
  rows.push_back({"feed per tooth (Eq. 18)", g(r.max_feed_per_tooth_m * 1e3) + " mm",
                  l.feed_per_tooth_limit_m ? g(*l.feed_per_tooth_limit_m * 1e3) + " mm" : "-",
                  !l.feed_per_tooth_limit_m ? ""
                  : r.max_feed_per_tooth_m > *l.feed_per_tooth_limit_m * (1.0 + 1e-9) ? "EXCEEDED"
                                                                                      : "within"});
  rep.table({"quantity", "largest along the path", "tool's limit", ""}, rows, "The tool's limits");
  if (!r.stretches.empty()) {
    std::vector<std::vector<std::string>> st;
    for (const process::FeedStretch& s : r.stretches)
      st.push_back({g(s.s0 * 1e3), g(s.s1 * 1e3), process::describe(s.binding)});
    rep.table({"from (mm)", "to (mm)", "what sets the feed"}, st, "The constant-force schedule");
  }
  rep.figure(process_figure(r), "The mean and peak cutting force and the feed along the path",
             "cutting force and feed against arc length");
}

}  // namespace polarcam
