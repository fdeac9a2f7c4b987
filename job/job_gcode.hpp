#pragma once
// The [gcode] table of a machine file (beside its [machine] table): how the machine takes G-code (axis letters,
// units, table radius, the arm's coupling, axis limits, feed mode, header and footer lines), every key checked
// (docs/job-format.md, docs/gcode.md). Only the job-parsing translation units include this.
#include <optional>

#include "machine/gcode/gcode.hpp"

namespace polarcam::jobfile {

class Section;

// The G-code spec of a [gcode] table, nullopt when the table is absent. `r_max` (the machine's largest radius)
// is the default table radius. Errors name the file, the line and the key.
// `machine_coupling` (m/rad, the [machine] coupling) is the default of the G-code coupling, in axis units.
std::optional<GcodeSpec> parse_gcode(Section& s, std::optional<double> r_max, double machine_coupling = 0.0);

}  // namespace polarcam::jobfile
