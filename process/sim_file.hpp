#pragma once
// The simulation files of `polarcam simulate` (TOML, docs/process.md): the A/C loop of Elbestawi 1980 (`ac`) and
// the band controller of Fussell & Gagne 1991 (`bands`). Values are plain numbers in SI units or quantities with
// units ("25.4 mm/s^2", "750 mm/min", "200 lbf"). Every key is checked: a missing, unknown or malformed key, a
// wrong unit or a value out of range is an InputError naming FILE:LINE and the key.
#include <optional>
#include <string>

#include "process/ac_loop.hpp"
#include "process/band_control.hpp"

namespace polarcam::process {

struct AcProblem {
  AcLoopSettings settings;
  std::optional<double> force_limit;  // [limit] force, N: a peak above it is reported (exit status 1)
};

struct BandProblem {
  BandSettings settings;
  std::optional<std::string> tool_file;  // [tool] file, resolved against the simulation file's folder
};

AcProblem read_ac_file(const std::string& path);
AcProblem parse_ac_toml(const std::string& text, const std::string& name);
BandProblem read_band_file(const std::string& path);
BandProblem parse_band_toml(const std::string& text, const std::string& name);

}  // namespace polarcam::process
