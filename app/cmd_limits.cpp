// polarcam limits TOOL.toml [--diameter D] [--length L] [--teeth Z] [--json]
// A cutting tool's limits (process/limits.hpp, docs/process.md): breakage force, stiffness, rapid feed per tooth
// (Elbestawi 1980), shank, tooth, feed-per-tooth and deflection limits (Fussell & Gagne 1991), chatter width.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "cam/format.hpp"
#include "job/tool_file.hpp"
#include "process/limits.hpp"

namespace polarcam::cli {
namespace cmd_limits {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string file, diameter, length;
  int teeth = 0;
  bool json = false;
};

constexpr double kDeg = std::numbers::pi / 180.0;

int run(const Opts& o) {
  process::Tool t = load_tool_file(o.file);
  if (!o.diameter.empty()) t.diameter_m = option_quantity(o.diameter, dim::length, "--diameter");
  if (!o.length.empty()) t.length_m = option_quantity(o.length, dim::length, "--length");
  if (o.teeth != 0) t.teeth = o.teeth;
  process::ToolLimits l;
  try {
    l = process::tool_limits(t);
  } catch (const InputError& e) {  // the file's tool passed its checks: an option, or numbers out of range
    const std::string opt = e.place() == "tool.diameter" ? "--diameter"
                            : e.place() == "tool.length" ? "--length"
                            : e.place() == "tool.teeth"  ? "--teeth"
                                                         : o.file + ": [" + e.place() + "]";
    throw InputError(e.message(), opt);
  }
  const double eq18 = process::fussell_eq18_constant(1.0), eq18_printed = process::fussell_eq18_constant(2.0);

  if (o.json) {
    nlohmann::ordered_json j;
    j["diameter_mm"] = t.diameter_m * 1e3;
    j["length_mm"] = t.length_m * 1e3;
    j["teeth"] = t.teeth;
    j["helix_angle_deg"] = t.helix_angle_rad / kDeg;
    j["breaking_stress_MPa"] = t.breaking_stress_Pa * 1e-6;
    j["youngs_modulus_GPa"] = t.youngs_modulus_Pa * 1e-9;
    j["yield_strength_MPa"] = t.yield_strength_Pa.value_or(t.breaking_stress_Pa) * 1e-6;
    j["safety_factor"] = t.safety_factor;
    if (t.deflection_tolerance_m) j["deflection_tolerance_mm"] = *t.deflection_tolerance_m * 1e3;
    j["second_moment_mm4"] = l.second_moment_m4 * 1e12;
    j["breakage_force_N"] = l.breakage_force_N;
    j["stiffness_N_per_m"] = l.stiffness_N_per_m;
    j["elbestawi_stiffness_N_per_m"] = l.elbestawi_stiffness_N_per_m;
    j["rapid_feed_per_tooth_mm"] = l.rapid_feed_per_tooth_m * 1e3;
    j["shank_force_limit_N"] = l.shank_force_limit_N;
    if (l.deflection_force_limit_N) j["deflection_force_limit_N"] = *l.deflection_force_limit_N;
    if (l.tooth_force_limit_N) j["tooth_force_limit_N"] = *l.tooth_force_limit_N;
    if (l.feed_per_tooth_limit_m) j["feed_per_tooth_limit_mm"] = *l.feed_per_tooth_limit_m * 1e3;
    if (l.chatter_limit_width_m) j["chatter_limit_width_mm"] = *l.chatter_limit_width_m * 1e3;
    j["eq18_constant"] = eq18;
    j["eq18_constant_printed_2piD"] = eq18_printed;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::ostringstream os;
  auto row = [&os](const char* name, const std::string& value, const char* source) {
    char b[160];
    std::snprintf(b, sizeof b, "  %-34s %-18s %s\n", name, value.c_str(), source);
    os << b;
  };
  auto g = [](double v, const char* unit) { return significant(v, 5) + " " + unit; };
  os << "tool " << o.file << ": d = " << significant(t.diameter_m * 1e3, 6) << " mm, L = "
     << significant(t.length_m * 1e3, 6) << " mm, " << t.teeth << " teeth, helix "
     << significant(t.helix_angle_rad / kDeg, 4) << " deg, sigma_S = " << significant(t.breaking_stress_Pa * 1e-6, 6)
     << " MPa, E = " << significant(t.youngs_modulus_Pa * 1e-9, 6) << " GPa\n";
  row("breakage force", g(l.breakage_force_N, "N"), "pi d^3 sigma_S / (32 L), Elbestawi Eq. 5.33");
  row("stiffness at the tip", g(l.stiffness_N_per_m * 1e-2, "N/cm"), "3 E I / L^3, Fussell & Gagne Eq. 20");
  row("stiffness of Eq. 5.34 as printed", g(l.elbestawi_stiffness_N_per_m * 1e-2, "N/cm"),
      "E I / (1.5 L^3), used by the rapid feed");
  row("rapid feed per tooth", g(l.rapid_feed_per_tooth_m * 1e3, "mm"), "0.9 (sigma_S/E) L^2/d, Elbestawi Eq. 5.35");
  row("shank force limit", g(l.shank_force_limit_N, "N"), "Fussell & Gagne Eq. 7");
  if (l.deflection_force_limit_N)
    row("deflection force limit", g(*l.deflection_force_limit_N, "N"), "y_tol 3 E I / L^3, Eq. 21");
  if (l.tooth_force_limit_N) row("tooth force limit", g(*l.tooth_force_limit_N, "N"), "Fussell & Gagne Eq. 13");
  if (l.feed_per_tooth_limit_m)
    row("feed per tooth limit", g(*l.feed_per_tooth_limit_m * 1e3, "mm"), "Fussell & Gagne Eq. 14-18 (pi D)");
  if (l.chatter_limit_width_m)
    row("chatter limit width of chip", g(*l.chatter_limit_width_m * 1e3, "mm"), "-1/(2 r Re(G)_min), Elbestawi Eq. 6.2");
  std::cout << os.str();
  return 0;
}

}  // namespace cmd_limits

void register_limits(CLI::App& app, Action& action) {
  using namespace cmd_limits;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "limits", "A cutting tool's limits: breakage force, stiffness, rapid feed per tooth, shank, tooth, "
                "feed-per-tooth and deflection limits, chatter width (docs/process.md)");
  c->add_option("tool", o->file, "tool file (TOML: [tool] diameter, length, teeth, ...)")->required();
  c->add_option("--diameter", o->diameter, "the tool's diameter instead of the file's, e.g. \"6.25 mm\"");
  c->add_option("--length", o->length, "the tool's overhang instead of the file's, e.g. \"50 mm\"");
  c->add_option("--teeth", o->teeth, "the number of teeth instead of the file's")->check(CLI::Range(1, 100));
  c->add_flag("--json", o->json, "print the inputs and limits as one JSON object (units in the keys)");
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
