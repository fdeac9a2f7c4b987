#include "process/chatter_file.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "cam/error.hpp"
#include "cam/input_file.hpp"
#include "cam/toml_table.hpp"
#include "cam/units.hpp"

namespace polarcam::process {
namespace {

}  // namespace

ChatterProblem parse_chatter_toml(const std::string& text, const std::string& name) {
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(std::string(e.description()), name + ":" + std::to_string(b.line) + ":" + std::to_string(b.column));
  }
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    if (key != "structure" && key != "cut" && key != "suppressor")
      throw InputError("unknown section [" + key + "] (expected [structure], [cut] and an optional [suppressor])",
                       toml_line_of(name, v));
    if (!v.is_table()) throw InputError("must be a table", toml_line_of(name, v) + ": key '" + key + "'");
  }
  if (!root["structure"].as_table()) throw InputError("missing the [structure] table (M_m, C_m, K_m, M_w, C_w, K_w)", name);
  if (!root["cut"].as_table()) throw InputError("missing the [cut] table (overlap, revolution_period)", name);
  TomlTable s{root["structure"].as_table(), name, "structure", {}};
  TomlTable c{root["cut"].as_table(), name, "cut", {}};
  const Dim damping = dim::mass / dim::time, stiffness = dim::mass / (dim::time * dim::time);
  ChatterProblem p;
  p.structure.M_m = s.require("M_m", dim::mass, "the machine's mass (kg)");
  p.structure.C_m = s.require("C_m", damping, "the machine's damping (N s/m)");
  p.structure.K_m = s.require("K_m", stiffness, "the machine's stiffness (N/m)");
  p.structure.M_w = s.require("M_w", dim::mass, "the workpiece's mass (kg)");
  p.structure.C_w = s.require("C_w", damping, "the workpiece's damping (N s/m)");
  p.structure.K_w = s.require("K_w", stiffness, "the workpiece's stiffness (N/m)");
  p.cut.overlap = c.require("overlap", dim::none, "the overlap of successive cuts mu (0 to 1)");
  p.cut.revolution_period = c.require("revolution_period", dim::time, "the revolution period T (s)");
  if (auto d = c.get("depth_of_cut", dim::length)) p.cut.depth = *d;
  s.finish();
  c.finish();
  if (const toml::table* st = root["suppressor"].as_table()) {
    TomlTable u{st, name, "suppressor", {}};
    SuppressorSpec q;
    q.sample_period = u.require("sample_period", dim::time, "the suppressor's sample period T_s (s)");
    q.step_size = u.require("step_size", dim::length, "the positioner's step size (m)");
    q.max_step_rate = u.require("max_step_rate", dim::frequency, "the stepper's largest step rate (steps/s, \"500 Hz\")");
    const std::string model = u.text("model").value_or("structure");
    if (model == "structure") {
      q.source = ModelSource::structure;
    } else if (model == "given") {
      q.source = ModelSource::given;
      q.omega_n = u.require("omega_n", dim::angular_speed, "the model's natural frequency (rad/s)");
      q.zeta = u.require("zeta", dim::none, "the model's damping ratio");
      q.gain = u.require("gain", dim::length / dim::force,
                         "the model's static gain (m/N)");
    } else if (model == "discrete") {
      q.source = ModelSource::discrete;
      q.A1 = u.require("A1", dim::length / dim::force, "A1 of Eq. 3.2 (m/N)");
      q.A2 = u.require("A2", dim::length / dim::force, "A2 of Eq. 3.2 (m/N)");
      q.B1 = u.require("B1", dim::none, "B1 of Eq. 3.2");
      q.B2 = u.require("B2", dim::none, "B2 of Eq. 3.2");
    } else {
      throw InputError("must be \"structure\", \"given\" or \"discrete\"", u.where("model"));
    }
    u.set("model_frequency_scale", dim::none, q.model_frequency_scale);
    u.finish();
    try {
      check(q);
    } catch (const InputError& e) {
      const std::string& key = e.place();
      throw InputError(e.message(), u.where(key.substr(key.find('.') + 1)));
    }
    p.suppressor = q;
  }
  try {
    check(p.structure, p.cut);
  } catch (const InputError& e) {
    // the check names section.key: give the file and line of that key
    const std::string& key = e.place();
    TomlTable& t = key.rfind("structure.", 0) == 0 ? s : c;
    const std::string k = key.substr(key.find('.') + 1);
    throw InputError(e.message(), t.where(k));
  }
  return p;
}

ChatterProblem read_chatter_file(const std::string& path) {
  return parse_chatter_toml(read_input_file(path), path);
}

}  // namespace polarcam::process
