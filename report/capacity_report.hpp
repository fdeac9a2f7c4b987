#pragma once
// What `polarcam capacity` prints and writes (and the report reuses): the largest speed and load as JSON or text,
// the capacity curve as CSV and as a figure. Formatting only: the numbers come from job_capacity.
#include <nlohmann/json.hpp>
#include <string>

#include "pipeline/job_capacity.hpp"
#include "report/plot.hpp"

namespace polarcam::cli {

nlohmann::ordered_json capacity_json(const Job& job, const JobCapacity& c);
std::string capacity_text(const Job& job, const JobCapacity& c);
// speed_mps,<measure>_<unit>,capped
std::string capacity_csv(const Job& job, const JobCapacity& c);
// The largest load against speed, the job's point, the step-rate limit.
plot::Figure capacity_figure(const Job& job, const JobCapacity& c);

}  // namespace polarcam::cli
