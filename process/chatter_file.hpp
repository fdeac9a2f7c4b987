#pragma once
// The chatter structure file (TOML, docs/chatter.md): [structure] M_m, C_m, K_m, M_w, C_w, K_w and [cut] overlap,
// revolution_period (and depth_of_cut for the time-domain simulation), each a plain number in SI units (kg,
// N s/m, N/m, a fraction, s, m) or a quantity with units ("0.2 s", "120 kN/m"); an optional [suppressor] table (the
// stepper chatter suppressor, process/suppressor.hpp): sample_period, step_size, max_step_rate, model = "structure"
// | "given" | "discrete" and that model's keys (omega_n, zeta, gain; A1, A2, B1, B2), model_frequency_scale. Every key is checked: a missing,
// unknown or malformed key, a wrong unit or a value out of range is an InputError naming FILE:LINE and the key.
#include <optional>
#include <string>

#include "process/structure.hpp"
#include "process/suppressor.hpp"

namespace polarcam::process {

struct ChatterProblem {
  TwoMassStructure structure;
  Cut cut;
  std::optional<SuppressorSpec> suppressor;  // the [suppressor] table, when the file has one
};

ChatterProblem read_chatter_file(const std::string& path);
// The same from TOML text; `name` is the file named in messages.
ChatterProblem parse_chatter_toml(const std::string& text, const std::string& name);

}  // namespace polarcam::process
