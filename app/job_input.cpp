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

Job load_job_input(const std::string& path, const PatternArgs& a) {
  PatternOptions o;
  o.machine_file = a.machine;
  if (!a.speed.empty()) {
    try {
      o.speed = parse_quantity_as(a.speed, dim::speed);
    } catch (const InputError& e) {
      throw InputError(e.message(), "--speed");
    }
  }
  return load_job_or_pattern(path, o);
}

}  // namespace polarcam::cli
