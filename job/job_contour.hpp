#pragma once
// [contour] of a job file: every contour kind polarcam knows (docs/job-format.md).
#include <nlohmann/json.hpp>

#include "job/toml_section.hpp"
#include "cam/curve.hpp"

namespace polarcam::jobfile {

// Builds the contour; `base_dir` resolves relative file names. Fills `prov` with a canonical description.
CurvePtr parse_contour(Section& s, const std::string& base_dir, nlohmann::ordered_json& prov, std::string& kind);

}  // namespace polarcam::jobfile
