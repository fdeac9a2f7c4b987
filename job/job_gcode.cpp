#include "job/job_gcode.hpp"

#include <cmath>

#include "cam/error.hpp"
#include "job/toml_section.hpp"

namespace polarcam::jobfile {
namespace {

// A list of strings (G-code lines); nullopt when the key is absent.
std::optional<std::vector<std::string>> lines(Section& s, const std::string& key) {
  const toml::node* n = s.node(key);
  if (!n) return std::nullopt;
  const toml::array* a = n->as_array();
  if (!a) s.fail(key, "expected a list of strings, e.g. [\"G21\", \"G90\"]");
  std::vector<std::string> out;
  for (size_t i = 0; i < a->size(); ++i) {
    auto v = a->get(i)->value<std::string>();
    if (!v) s.fail(key, "item " + std::to_string(i + 1) + " is not a string");
    out.push_back(*v);
  }
  return out;
}

}  // namespace

std::optional<GcodeSpec> parse_gcode(Section& s, std::optional<double> r_max, double machine_coupling) {
  if (!s.present()) return std::nullopt;
  GcodeSpec g;
  g.theta_axis = s.string("theta_axis").value_or(g.theta_axis);
  g.rho_axis = s.string("rho_axis").value_or(g.rho_axis);
  g.theta_units_per_rad = s.number("theta_units_per_rad").value_or(g.theta_units_per_rad);
  g.rho_units_per_radius = s.number("rho_units_per_radius").value_or(g.rho_units_per_radius);
  if (auto r = s.quantity("table_radius", dim::length)) {
    g.table_radius = *r;
  } else if (r_max) {
    g.table_radius = *r_max;
  } else {
    s.fail_section("give 'table_radius' (the radius rho = 1 stands for), or r_max in [machine]");
  }
  // the machine's coupling (m of radius per radian) in radial axis units, unless the table gives its own
  const double from_machine = machine_coupling * g.rho_units_per_radius / g.table_radius;
  g.coupling = s.number("coupling").value_or(from_machine);
  if (machine_coupling != 0.0 && std::abs(g.coupling - from_machine) > 1e-9 * std::abs(from_machine))
    s.fail("coupling", "disagrees with the [machine] coupling, which is " + std::to_string(from_machine) +
                           " radial axis units per radian: leave it out to use that");
  const std::optional<double> theta_max_feed = s.number("theta_max_feed"), rho_max_feed = s.number("rho_max_feed");
  const std::string mode = s.string("feed_mode").value_or("inverse_time");
  if (mode == "inverse_time") {
    g.feed_mode = FeedMode::inverse_time;
  } else if (mode == "axis") {
    g.feed_mode = FeedMode::axis;
  } else {
    s.fail("feed_mode", "must be \"inverse_time\" or \"axis\"");
  }
  g.axis_feed = s.number("axis_feed").value_or(0.0);
  if (auto h = lines(s, "header")) g.header = *h;
  if (auto f = lines(s, "footer")) g.footer = *f;
  if (auto u = lines(s, "pen_up")) g.pen_up = *u;
  if (auto d = lines(s, "pen_down")) g.pen_down = *d;
  if (auto d = s.integer("decimals")) {
    if (*d < 1 || *d > 9) s.fail("decimals", "must be a whole number from 1 to 9");
    g.decimals = static_cast<int>(*d);
  }
  s.finish();  // unknown keys first: a misspelt key is named as such, not as the one it misses
  for (const char* key : {"theta_max_feed", "rho_max_feed"})
    if (!s.has(key)) s.fail(key, "is missing: give the axis's largest rate in its units per minute");
  g.theta_max_feed = *theta_max_feed;
  g.rho_max_feed = *rho_max_feed;
  // the checks of the spec itself, named by their key here; axis_feed is checked when the axis mode is used
  try {
    GcodeSpec probe = g;
    probe.feed_mode = FeedMode::inverse_time;
    validate(probe);
  } catch (const InputError& e) {
    s.fail(e.place(), e.message());
  }
  if (s.has("axis_feed") && !(g.axis_feed > 0.0)) s.fail("axis_feed", "must be a positive rate in axis units per minute");
  if (g.feed_mode == FeedMode::axis && !(g.axis_feed > 0.0))
    s.fail_section("feed_mode \"axis\" needs 'axis_feed' (F in axis units per minute)");
  return g;
}

}  // namespace polarcam::jobfile
