#pragma once
// What `polarcam analyze` prints and writes: the summary (text or JSON), the series along the path (CSV) and the
// torque-ratio plots of Figures 5.8-5.25 of the thesis. Formatting only: the numbers come from job_analysis.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/job_analysis.hpp"
#include "report/plot.hpp"

namespace polarcam::cli {

// Short label of a case's load and speed, e.g. "V = 1.52 cm/s, M = 14.6 kg".
std::string case_label(const CaseResult& c);

nlohmann::ordered_json case_json(const Job& job, const CaseResult& c);
std::string case_text(const Job& job, const CaseResult& c);
// One-line verdict, e.g. "GO" or "NO-GO: radial axis needs 1.26 x ...".
std::string verdict_line(const Job& job, const CaseResult& c);

// A time-optimal schedule against the best constant speed (docs/time-optimal.md): total times, saving, the binding
// constraint of each stretch; the text is one line per item, indented as case_text.
nlohmann::ordered_json speed_plan_json(const SpeedPlan& p);
std::string speed_plan_text(const SpeedPlan& p);
// The schedule at its stations: s_m,t_s,speed_mps,accel_mps2 (the acceleration up to the next station),phase,binding.
std::string speed_plan_csv(const SpeedPlan& p);

// The series of every case; a leading `case` column when there are several.
std::string series_csv(const Job& job, const std::vector<CaseResult>& cases);

// Radial and angular torque ratio against theta. Several speeds and several loads: one column per speed, one
// curve per load (the thesis's layout); otherwise one curve per case.
plot::Figure torque_ratio_figure(const Job& job, const std::vector<CaseResult>& cases);

}  // namespace polarcam::cli
