#pragma once
// Rendering `polarcam process` (pipeline/job_process.hpp): the JSON and text summaries, the series along the path
// as CSV, the figure of force and feed against arc length. Nothing here computes a number of the cut.
#include <nlohmann/json.hpp>
#include <string>

#include "pipeline/job_process.hpp"
#include "report/plot.hpp"

namespace polarcam {

nlohmann::ordered_json process_json(const Job& job, const ProcessRun& r);
std::string process_text(const Job& job, const ProcessRun& r);
// s_m,t_s,speed_mm_per_s,feed_per_tooth_mm,engaged_angle_deg,feed_force_N,normal_force_N,mean_force_N,
// peak_force_N,peak_tooth_force_N,peak_normal_force_N,binding: one row per station.
std::string process_csv(const ProcessRun& r);
plot::Figure process_figure(const ProcessRun& r);

}  // namespace polarcam
