#pragma once
// Tool files (examples/process/*.toml): a cutting tool for the process limits (process/tool.hpp, docs/process.md).
//
//   [tool]       diameter, length (overhang from the holder), teeth, helix_angle, breaking_stress, youngs_modulus;
//                optional yield_strength, safety_factor, deflection_tolerance
//   [tooth]      optional: thickness, width, length (Fussell & Gagne's tooth model)
//   [cut]        optional, with [tooth]: spindle_speed, axial_depth, radial_depth, material_constant
//   [structure]  optional: re_g_min (m/N, negative), cutting_stiffness (r of Elbestawi's Eq. 6.1)
//
// Every key is checked; an error names the file, the line and the key and says what to change (InputError).
#include <string>

#include "process/tool.hpp"

namespace polarcam {

process::Tool load_tool_file(const std::string& path);

}  // namespace polarcam
