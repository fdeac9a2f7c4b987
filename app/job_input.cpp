// --machine and --speed: a pattern file as a job (job/pattern.hpp).
#include "app/cli.hpp"
#include "cam/error.hpp"
#include "cam/units.hpp"
#include "job/pattern.hpp"

namespace polarcam::cli {

void add_pattern_options(CLI::App* c, PatternArgs& a, bool with_speed) {
  c->add_option("--machine", a.machine, "machine file, for a pattern file (.thr, .svg, .dxf, .csv) given in place of a job");
  if (with_speed)
    c->add_option("--speed", a.speed, "speed along the path, e.g. \"40 mm/s\" (a pattern needs it; overrides a job's)");
}

double option_quantity(const std::string& text, const Dim& d, const std::string& option) {
  try {
    return parse_quantity_as(text, d);
  } catch (const InputError& e) {
    throw InputError(e.message(), option);
  }
}

Job load_job_input(const std::string& path, const PatternArgs& a, double tolerance) {
  PatternOptions o;
  o.machine_file = a.machine;
  o.tolerance = tolerance;
  if (!a.speed.empty()) o.speed = option_quantity(a.speed, dim::speed, "--speed");
  return load_job_or_pattern(path, o);
}

}  // namespace polarcam::cli
