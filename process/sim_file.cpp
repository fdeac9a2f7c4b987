#include "process/sim_file.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "cam/error.hpp"
#include "cam/input_file.hpp"
#include "cam/toml_table.hpp"
#include "cam/units.hpp"

namespace polarcam::process {
namespace {

toml::table parse_root(const std::string& text, const std::string& name, const std::set<std::string>& sections) {
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(std::string(e.description()), name + ":" + std::to_string(b.line) + ":" + std::to_string(b.column));
  }
  std::string list;
  for (const auto& s : sections) list += (list.empty() ? "[" : ", [") + s + "]";
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    if (!sections.count(key)) throw InputError("unknown section [" + key + "] (expected " + list + ")", toml_line_of(name, v));
    if (key != "band" && !v.is_table()) throw InputError("must be a table", toml_line_of(name, v) + ": key '" + key + "'");
  }
  return root;
}


// A check's InputError names section.key: give the file and line of that key.
[[noreturn]] void relocate(const InputError& e, std::map<std::string, TomlTable*>& tables, const std::string& file) {
  const std::string& key = e.place();
  const size_t dot = key.find('.');
  if (dot != std::string::npos) {
    auto it = tables.find(key.substr(0, dot));
    if (it != tables.end()) throw InputError(e.message(), it->second->where(key.substr(dot + 1)));
  }
  throw InputError(e.message(), file + ": " + (key.empty() ? "" : "key '" + key + "'"));
}

constexpr Dim kStiffness = dim::force / dim::length;

}  // namespace

AcProblem parse_ac_toml(const std::string& text, const std::string& name) {
  toml::table root = parse_root(text, name, {"servo", "dda", "control", "cut", "simulation", "limit"});
  for (const char* need : {"control", "cut", "simulation"})
    if (!root[need].as_table()) throw InputError(std::string("missing the [") + need + "] table", name);
  TomlTable sv{root["servo"].as_table(), name, "servo", {}};
  TomlTable dd{root["dda"].as_table(), name, "dda", {}};
  TomlTable ct{root["control"].as_table(), name, "control", {}};
  TomlTable cu{root["cut"].as_table(), name, "cut", {}};
  TomlTable si{root["simulation"].as_table(), name, "simulation", {}};
  TomlTable li{root["limit"].as_table(), name, "limit", {}};
  AcProblem p;
  AcLoopSettings& s = p.settings;
  sv.set("gain", dim::frequency * dim::frequency, s.servo.gain);
  sv.set("pole1", dim::frequency, s.servo.pole1);
  sv.set("pole2", dim::frequency, s.servo.pole2);
  dd.set("rate", dim::frequency, s.dda_rate_hz);
  dd.set("blu", dim::length, s.blu_m);
  s.control_period_s = 1.0 / s.dda_rate_hz;
  ct.set("period", dim::time, s.control_period_s);
  if (auto st = ct.text("strategy")) {
    if (*st == "A") s.strategy = ImpactStrategy::A;
    else if (*st == "B") s.strategy = ImpactStrategy::B;
    else if (*st == "none") s.strategy = ImpactStrategy::none;
    else throw InputError("must be \"A\", \"B\" or \"none\"", ct.where("strategy"));
  }
  s.K_ac = ct.require("K_ac", dim::acceleration, "the integral gain K_ac (\"25.4 mm/s^2\")");
  s.B = ct.require("B", dim::speed, "the proportional gain B (\"1.0 mm/s\")");
  s.F_nom = ct.require("F_nom", dim::force, "the nominal force F_nom (\"1320 N\")");
  ct.set("rapid_feed", dim::speed, s.rapid_feed);
  ct.set("impact_threshold", dim::force, s.impact_threshold);
  ct.set("slow_feed", dim::speed, s.slow_feed);
  ct.set("slow_time", dim::time, s.slow_time);
  ct.set("hold_time", dim::time, s.hold_time);
  ct.set("reduced_gain_time", dim::time, s.reduced_gain_time);
  if (auto z = cu.integer("teeth")) s.teeth = *z;
  else throw InputError("missing: give the number of teeth", name + ": key 'cut.teeth'");
  s.spindle_speed_rad_s = cu.require("spindle_speed", dim::angular_speed, "the spindle speed (\"600 rpm\")");
  s.cutting_stiffness = cu.require("cutting_stiffness", kStiffness, "the cutting stiffness K_C (\"8970 N/mm\")");
  s.spindle_stiffness = cu.get("spindle_stiffness", kStiffness);
  cu.set("entry_distance", dim::length, s.entry_distance);
  s.duration_s = si.require("duration", dim::time, "the simulated time (\"1 s\")");
  p.force_limit = li.get("force", dim::force);
  for (TomlTable* t : {&sv, &dd, &ct, &cu, &si, &li}) t->finish();
  if (p.force_limit && !(*p.force_limit > 0.0)) throw InputError("must be a positive force", li.where("force"));
  std::map<std::string, TomlTable*> tables{{"servo", &sv}, {"dda", &dd}, {"control", &ct}, {"cut", &cu},
                                       {"simulation", &si}};
  try {
    check(s);
  } catch (const InputError& e) {
    relocate(e, tables, name);
  }
  return p;
}

AcProblem read_ac_file(const std::string& path) { return parse_ac_toml(read_input_file(path), path); }

BandProblem parse_band_toml(const std::string& text, const std::string& name) {
  toml::table root = parse_root(text, name, {"controller", "plant", "cut", "simulation", "tool", "band"});
  for (const char* need : {"controller", "cut", "simulation"})
    if (!root[need].as_table()) throw InputError(std::string("missing the [") + need + "] table", name);
  TomlTable co{root["controller"].as_table(), name, "controller", {}};
  TomlTable pl{root["plant"].as_table(), name, "plant", {}};
  TomlTable cu{root["cut"].as_table(), name, "cut", {}};
  TomlTable si{root["simulation"].as_table(), name, "simulation", {}};
  TomlTable to{root["tool"].as_table(), name, "tool", {}};
  BandProblem p;
  BandSettings& s = p.settings;
  co.set("rate", dim::frequency, s.rate_hz);
  co.set("step", dim::none, s.step_fraction);
  s.programmed_feed = co.require("programmed_feed", dim::speed, "the programmed feed (\"30 in/min\")");
  co.set("initial_override", dim::none, s.initial_override);
  co.set("max_override", dim::none, s.max_override);
  pl.set("drive_time_constant", dim::time, s.drive_time_constant);
  if (auto f = pl.get("filter_cutoff", dim::frequency)) s.filter_cutoff_hz = *f;
  if (auto off = pl.text("filter")) {
    if (*off != "none") throw InputError("must be \"none\" (no sensor filter) or left out", pl.where("filter"));
    if (pl.t->get("filter_cutoff")) throw InputError("give either filter = \"none\" or filter_cutoff", pl.where("filter"));
    s.filter_cutoff_hz.reset();
  }
  pl.set("rate", dim::frequency, s.sim_rate_hz);
  BandCut& c = s.cut;
  if (auto z = cu.integer("teeth")) c.teeth = *z;
  else throw InputError("missing: give the number of teeth", name + ": key 'cut.teeth'");
  c.spindle_speed_rad_s = cu.require("spindle_speed", dim::angular_speed, "the spindle speed (\"2000 rpm\")");
  c.specific_force = cu.require("specific_force", dim::force / (dim::length * dim::area),
                                "the specific force k of F = k a b f_t (\"180 N/mm^3\")");
  c.radial_depth = cu.require("radial_depth", dim::length, "the radial depth a (\"0.25 in\")");
  c.axial_depth = cu.require("axial_depth", dim::length, "the axial depth b (\"0.25 in\")");
  c.step_time = cu.get("step_time", dim::time);
  if (auto b2 = cu.get("step_axial_depth", dim::length)) c.step_axial_depth = *b2;
  if (c.step_time.has_value() != (cu.t && cu.t->get("step_axial_depth") != nullptr))
    throw InputError("give step_time and step_axial_depth together", cu.where(c.step_time ? "step_time" : "step_axial_depth"));
  cu.set("perpendicular_ratio", dim::none, c.perpendicular_ratio);
  s.duration_s = si.require("duration", dim::time, "the simulated time (\"3 s\")");
  if (auto f = to.text("file")) {
    if (f->empty()) throw InputError("must name a tool file", to.where("file"));
    std::filesystem::path tp(*f);
    if (tp.is_relative()) tp = std::filesystem::path(name).parent_path() / tp;
    p.tool_file = tp.lexically_normal().string();
  }
  // the bands, in the order of their rank (the first listed wins when several are active)
  const toml::node* bn = root.get("band");
  const toml::array* arr = bn ? bn->as_array() : nullptr;
  if (bn && !arr) throw InputError("must be an array of tables: write each band as [[band]]", toml_line_of(name, *bn));
  if (!arr || arr->empty()) throw InputError("missing: give at least one [[band]] (event, quantity, lower, upper)", name);
  std::set<std::string> events;
  for (const toml::node& n : *arr) {
    const toml::table* bt = n.as_table();
    if (!bt) throw InputError("each [[band]] must be a table", toml_line_of(name, n));
    TomlTable b{bt, name, "band", {}};
    Band band;
    auto ev = b.text("event");
    if (!ev || ev->empty()) throw InputError("missing: give the band's event (\"shank failure\")", toml_line_of(name, n));
    band.event = *ev;
    if (!events.insert(band.event).second) throw InputError("the event '" + band.event + "' has two bands", b.where("event"));
    b.name = "band." + band.event;
    const std::string q = b.text("quantity").value_or("");
    Dim d = dim::force;
    if (q == "total_force") band.quantity = BandQuantity::total_force;
    else if (q == "perpendicular_force") band.quantity = BandQuantity::perpendicular_force;
    else if (q == "feed_per_tooth") {
      band.quantity = BandQuantity::feed_per_tooth;
      d = dim::length;
    } else {
      throw InputError("must be \"total_force\", \"perpendicular_force\" or \"feed_per_tooth\"", b.where("quantity"));
    }
    band.lower = b.require("lower", d, "the band's lower limit");
    band.upper = b.require("upper", d, "the band's upper limit");
    b.finish();
    if (!(band.lower >= 0.0)) throw InputError("must be 0 or more", b.where("lower"));
    if (!(band.upper > band.lower)) throw InputError("must be above the band's lower limit", b.where("upper"));
    s.bands.push_back(band);
  }
  for (TomlTable* t : {&co, &pl, &cu, &si, &to}) t->finish();
  std::map<std::string, TomlTable*> tables{{"controller", &co}, {"plant", &pl}, {"cut", &cu}, {"simulation", &si}};
  try {
    check(s);
  } catch (const InputError& e) {
    relocate(e, tables, name);
  }
  return p;
}

BandProblem read_band_file(const std::string& path) { return parse_band_toml(read_input_file(path), path); }

}  // namespace polarcam::process
