#pragma once
// Numbers in the reports' text and JSON, shared by the report files (each brings what it uses into its own
// unnamed namespace with a using-declaration).
#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace polarcam::report_numbers {

// v to `prec` significant digits, as printf's %g writes it ("0.0254", "1.5e+06").
inline std::string g(double v, int prec = 4) { return fmt::format("{:.{}g}", v, prec); }
// A number for JSON, null where it is not finite (JSON has no infinity).
inline nlohmann::ordered_json num(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}
// A number for JSON that may be missing: null then.
inline nlohmann::ordered_json optional_number(const std::optional<double>& v) {
  return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json();
}
// The axis's name: 0 radial, 1 angular.
inline const char* axis_name(int axis) { return axis == 0 ? "radial" : "angular"; }

}  // namespace polarcam::report_numbers
