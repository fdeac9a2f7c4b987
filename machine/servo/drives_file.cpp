#include "machine/servo/drives_file.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

#include "cam/error.hpp"
#include "cam/input_file.hpp"
#include "cam/toml_table.hpp"
#include "cam/units.hpp"

namespace polarcam::servo {
namespace {

constexpr double kPi = 3.14159265358979323846;

// "count" is the encoder count, a pure number: "0.0781 V/count" is 0.0781 V, "636.62 count/rad" is 636.62 /rad.
std::string without_counts(const std::string& s) {
  static const std::regex per_count(R"(\s*/\s*counts?\b)"), count(R"(\bcounts?\b)");
  return std::regex_replace(std::regex_replace(s, per_count, ""), count, "");
}

AxisDrive read_axis(TomlTable& t, bool rotary) {
  using namespace dim;
  const Dim per_rad = none / angle, torque_s = torque * time / angle;
  AxisDrive d;
  d.name = t.name;
  d.rotary = rotary;
  ServoParams& p = d.params;
  p.R_a = t.require("R_a", resistance, "the armature resistance (\"0.4 ohm\")");
  p.L_a = t.require("L_a", inductance, "the armature inductance (\"2 mH\")");
  p.K_t = t.require("K_t", torque / current, "the torque constant (\"0.3 N m/A\")");
  p.K_b = t.require("K_b", voltage * time / angle, "the back-emf constant (\"0.3 V s/rad\")");
  p.J_e = t.require("J_e", inertia, "the inertia on the motor shaft (\"0.0036 kg m^2\")");
  p.B = t.require("B", torque_s, "the viscous friction (\"0.09 N m s/rad\")");
  p.K_a = t.require("K_a", none, "the current feedback gain (A/A)");
  p.K_I = t.require("K_I", current / voltage, "the current amplifier gain (\"25.5 A/V\")");
  p.K_v = t.require("K_v", none, "the PWM gain (V/V)");
  p.H_g = t.require("H_g", voltage * time / angle, "the tachogenerator gain (\"0.08872 V s/rad\")");
  p.T_g = t.require("T_g", none, "the tachogenerator attenuation (V/V)");
  p.S_g = t.require("S_g", none, "the command preamplifier gain (V/V)");
  p.K_e = t.require("K_e", per_rad, "the encoder gain (\"636.62 count/rad\")");
  p.K_d = t.require("K_d", voltage, "the DAC gain (\"0.0781 V/count\")");
  p.K_p = t.require("K_p", none, "the filter gain K_p of D(z) = K_p (z + a)/(z + b)");
  p.a = t.require("a", none, "the filter zero a of D(z) = K_p (z + a)/(z + b)");
  p.b = t.require("b", none, "the filter pole b of D(z) = K_p (z + a)/(z + b)");
  p.T = t.require("sample_period", time, "the position loop's sample period (\"1 ms\")");
  if (auto v = t.get("C_I", frequency)) p.C_I = *v;
  if (auto v = t.get("coulomb", torque)) p.coulomb = *v;
  if (auto v = t.get("peak_current", current)) {
    if (!(*v > 0.0)) throw InputError("must be a positive current", t.where("peak_current"));
    d.peak_current = *v;
  }
  if (rotary) {
    d.ratio = t.require("ratio", none, "the motor revolutions per revolution of the arm (a worm's ratio)");
    if (!(d.ratio > 0.0 && d.ratio < 1e6)) throw InputError("must be above 0 and below 1e6", t.where("ratio"));
  } else {
    d.pitch = t.require("pitch", length, "the travel per motor revolution (\"5.08 mm\")");
    if (!(d.pitch > 0.0 && d.pitch < 10.0)) throw InputError("must be above 0 and below 10 m", t.where("pitch"));
  }
  t.finish();
  try {
    check(p);
  } catch (const InputError& e) {
    throw InputError(e.message(), t.where(e.place()));
  }
  return d;
}

}  // namespace

double AxisDrive::per_count() const {
  const double per_motor_rad = rotary ? 1.0 / ratio : pitch / (2.0 * kPi);
  return per_motor_rad / params.K_e;
}

Drives parse_drives_toml(const std::string& text, const std::string& name) {
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(std::string(e.description()), name + ":" + std::to_string(b.line) + ":" + std::to_string(b.column));
  }
  Drives d;
  const bool cartesian = root.contains("x") || root.contains("y");
  d.polar = !cartesian && (root.contains("r") || root.contains("theta"));
  const char* names[2] = {d.polar ? "r" : "x", d.polar ? "theta" : "y"};
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    if (key == "source") {
      if (!v.is_string()) throw InputError("must be a string", toml_line_of(name, v) + ": key 'source'");
      d.source = *v.value<std::string>();
      continue;
    }
    if (key != names[0] && key != names[1])
      throw InputError("unknown table [" + key + "] (expected [x] and [y], or [r] and [theta])", toml_line_of(name, v));
    if (!v.is_table()) throw InputError("must be a table", toml_line_of(name, v) + ": key '" + key + "'");
  }
  for (int i = 0; i < 2; ++i) {
    if (!root[names[i]].as_table())
      throw InputError(std::string("missing the [") + names[i] + "] table (the drives of both axes: [x] and [y], or [r] and [theta])", name);
    TomlTable t{root[names[i]].as_table(), name, names[i], {}, without_counts};
    d.axis[i] = read_axis(t, d.polar && i == 1);
  }
  if (d.axis[0].params.T != d.axis[1].params.T)
    throw InputError("must equal [" + std::string(names[0]) + "].sample_period: one controller samples both axes",
                     TomlTable{root[names[1]].as_table(), name, names[1], {}, without_counts}.where("sample_period"));
  return d;
}

Drives read_drives_file(const std::string& path) {
  return parse_drives_toml(read_input_file(path), path);
}

}  // namespace polarcam::servo
