#pragma once
// Table 5.1 of the thesis read from the shared reference data (tests/data holds a copy of the same file), for the
// dynamics reference test and the check that the example machine file carries the same numbers.
#include <toml++/toml.h>

#include <filesystem>
#include <numbers>
#include <optional>
#include <string>

#include "cam/units.hpp"

namespace polarcam::test {

struct Reference {
  double M_c, J_A, FfLA, K1, K2, k_theta, k_R;  // Table 5.1 (k_R in rev/m)
  double V_supply, K_V, K_T, R_a, L_a, c_pullout;
  int N_s;
  double V_tool, width, k_c, c1, depth;  // grinding
};

inline double reference_quantity(const toml::table& t, const char* key, const Dim& d) {
  return parse_quantity_as(*t[key].value<std::string>(), d);
}

inline std::optional<Reference> read_reference() {
  std::filesystem::path p = std::filesystem::path(POLARCAM_SHARED_DIR) / "reference" / "fahim1983.toml";
  if (!std::filesystem::exists(p))  // the repository's copy of the same file
    p = std::filesystem::path(POLARCAM_SOURCE_DIR) / "tests" / "data" / "fahim1983_reference.toml";
  if (!std::filesystem::exists(p)) return std::nullopt;
  const toml::table root = toml::parse_file(p.string());
  const toml::table& m = *root["machine"].as_table();
  const toml::table& st = *m["stepper"].as_table();
  const toml::table& gr = *root["operating"]["grinding"].as_table();
  Reference r;
  r.M_c = reference_quantity(m, "carriage_equivalent_mass", dim::mass);
  r.J_A = reference_quantity(m, "arm_equivalent_inertia", dim::inertia);
  r.FfLA = reference_quantity(m, "arm_support_friction_torque", dim::torque);
  r.K1 = *m["K1_worm"].value<double>();
  r.K2 = reference_quantity(m, "K2_screw", dim::length);
  r.k_theta = *m["k_theta"].value<double>();
  r.k_R = reference_quantity(m, "k_R", dim::angle / dim::length) / (2 * std::numbers::pi);  // rev/m
  r.V_supply = reference_quantity(st, "supply_voltage", dim::voltage);
  r.K_V = reference_quantity(st, "K_V", dim::voltage * dim::time / dim::angle);
  r.K_T = reference_quantity(st, "K_T", dim::torque / dim::current);
  r.N_s = static_cast<int>(*st["rotor_teeth"].value<int64_t>());
  r.R_a = reference_quantity(st, "R_a", dim::resistance);
  r.L_a = reference_quantity(st, "L_a", dim::inductance);
  r.c_pullout = *st["pullout_constant"].value<double>();
  r.V_tool = reference_quantity(gr, "tool_peripheral_speed", dim::speed);
  r.width = reference_quantity(gr, "width_of_cut", dim::length);
  r.k_c = reference_quantity(gr, "k_c", dim::pressure);
  r.c1 = *gr["c1"].value<double>();
  r.depth = parse_quantity_as(*gr["depths_of_cut"][0].value<std::string>(), dim::length);
  return r;
}

}  // namespace polarcam::test
