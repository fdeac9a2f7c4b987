#pragma once
// [optimize] of a job file: options of `polarcam optimize` (docs/job-format.md, docs/area-error.md).
#include "job/toml_section.hpp"
#include "optimize/placement.hpp"

namespace polarcam::jobfile {

// Reads the section (absent: defaults); every key is checked, unknown keys are errors.
PlacementOptions parse_optimize(Section& s);

}  // namespace polarcam::jobfile
