#pragma once
// The drives file (TOML, docs/feed-drives.md): one table per axis, [x] and [y] for a Cartesian machine or [r]
// and [theta] for a polar one, each with the servo parameters under their symbols in J. Peng's Appendix A (R_a,
// L_a, K_t, K_b, J_e, B, K_a, K_I, K_v, H_g, T_g, S_g, K_e, K_d, K_p, a, b, sample_period; C_I, coulomb and
// peak_current optional) as quantities with units ("0.4 ohm", "0.3 N m/A", "636.62 count/rad"; "count" is the encoder count,
// a pure number) or plain numbers in SI, and the axis's transmission: `pitch` (length per motor revolution: a
// lead screw) on x, y and r, `ratio` (motor revolutions per revolution of the arm: a worm) on theta. A top-level
// `source` string may say where the numbers come from. Every key is checked: a missing, unknown or malformed key,
// a wrong unit or a value out of range is an InputError naming FILE:LINE and the key.
#include <string>

#include "machine/servo/servo_axis.hpp"

namespace polarcam::servo {

struct AxisDrive {
  std::string name;      // "x", "y", "r", "theta"
  ServoParams params;
  bool rotary = false;   // theta: positions in rad, else m
  double pitch = 0.0;    // m per motor revolution (linear axes)
  double ratio = 0.0;    // motor revolutions per axis revolution (rotary axis)
  double peak_current = 0.0;  // the amplifier's peak current (A), 0 when not given: reported, not modelled
  // The axis's position (m or rad) per encoder count.
  double per_count() const;
};

struct Drives {
  bool polar = false;     // axes r, theta; else x, y
  AxisDrive axis[2];
  std::string source;
};

Drives read_drives_file(const std::string& path);
// The same from TOML text; `name` is the file named in messages.
Drives parse_drives_toml(const std::string& text, const std::string& name);

}  // namespace polarcam::servo
