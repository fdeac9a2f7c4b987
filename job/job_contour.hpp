#pragma once
// [contour] of a job file: every contour kind polarcam knows (docs/job-format.md).
#include <nlohmann/json.hpp>

#include "job/toml_section.hpp"
#include <optional>

#include "cam/curve.hpp"
#include "cam/thr_file.hpp"

namespace polarcam::jobfile {

// Builds the contour; `base_dir` resolves relative file names; `table_radius` is the machine's r_max, the radius
// a theta-rho pattern's rho = 1 means unless the contour gives `rho_scale`. Fills `prov` with a canonical
// description.
CurvePtr parse_contour(Section& s, const std::string& base_dir, nlohmann::ordered_json& prov, std::string& kind,
                       std::optional<double> table_radius);

// Points joined by straight lines (repeated points merged), closed back to the first when `closed`.
CurvePtr polyline_contour(const std::vector<Vec2>& pts, bool closed);

// A theta-rho pattern (rho 0..1) as a contour: rho scaled by `rho_scale` (m), named after `source`; fills `prov`
// (kind, file, scale, counts, a CRC of the vertices).
CurvePtr theta_rho_contour(const ThrPattern& p, double rho_scale, const std::string& source,
                           nlohmann::ordered_json& prov);

}  // namespace polarcam::jobfile
