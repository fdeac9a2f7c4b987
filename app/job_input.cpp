// --machine and --speed: a pattern file as a job (job/pattern.hpp).
#include "app/cli.hpp"

#include <cmath>
#include <cstdio>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/image_trace.hpp"
#include "cam/units.hpp"
#include "job/pattern.hpp"
#include "pipeline/job_tape.hpp"

namespace polarcam::cli {

void add_pattern_options(CLI::App* c, PatternArgs& a, bool with_speed) {
  c->add_option("--machine", a.machine, "machine file, for a pattern file (.thr, .svg, .dxf, .csv, .png, .pbm, .pgm) given in place of a job");
  if (with_speed)
    c->add_option("--speed", a.speed, "speed along the path, e.g. \"40 mm/s\" (a pattern needs it; overrides a job's)");
  add_trace_options(c, a);
}

void add_trace_options(CLI::App* c, PatternArgs& a) {
  a.trace_given[0] = c->add_option("--pixel-size", a.pixel_size, "an image's pixel size, e.g. \"0.1 mm\" (default: the image's own resolution)");
  a.trace_given[1] = c->add_option("--threshold", a.threshold, "an image's ink: pixels darker than this gray level, 0..1 (default 0.5)");
  a.trace_given[2] = c->add_flag("--invert", a.invert, "an image's ink is light on dark paper");
  a.trace_given[3] = c->add_option("--despeckle", a.despeckle, "drop an image's spots of at most this many pixels (default 2)");
}

void check_trace_options_apply(const PatternArgs& a, const std::string& input) {
  static const char* const kNames[4] = {"--pixel-size", "--threshold", "--invert", "--despeckle"};
  if (is_image_file(input)) return;
  for (int i = 0; i < 4; ++i)
    if (option_given(a.trace_given[i]))
      throw InputError("traces a template image (.png, .pbm, .pgm); " + input + " is not one, so it would be ignored",
                       kNames[i]);
}

TraceOptions trace_options(const PatternArgs& a) {
  TraceOptions t;
  if (!a.pixel_size.empty()) t.pixel_size_m = option_quantity(a.pixel_size, dim::length, "--pixel-size");
  t.threshold = a.threshold;
  t.invert = a.invert;
  t.despeckle = a.despeckle;
  return t;
}

double option_quantity(const std::string& text, const Dim& d, const std::string& option) {
  try {
    return parse_quantity_as(text, d);
  } catch (const InputError& e) {
    throw InputError(e.message(), option);
  }
}

void add_safety_factor_option(CLI::App* c, SafetyFactor& sf) {
  sf.option = c->add_option("--safety-factor", sf.value, "safety factor instead of the job's [limits] (>= 1)");
}

void apply_safety_factor(const SafetyFactor& sf, Job& job) {
  if (!option_given(sf.option)) return;
  if (!(sf.value >= 1.0) || !std::isfinite(sf.value)) throw InputError("must be at least 1", "--safety-factor");
  job.safety_factor = sf.value;
}

void warn_step_rate_excess(const Job& job, const DigitizeResult& r) {
  for (const StepRateExcess& e : step_rate_excess(job, r))
    std::fprintf(stderr,
                 "warning: the %s motor would step at %s steps/s (%s tape steps/s x %s), above its max_step_rate "
                 "of %s steps/s: lower the speed or replay the tape slower\n",
                 e.axis == 0 ? "radial" : "angular", significant(e.motor_rate_hz, 5).c_str(),
                 significant(e.tape_rate_hz, 5).c_str(), significant(e.motor_steps_per_tape_step, 4).c_str(),
                 significant(e.limit_hz, 5).c_str());
}

Job load_job_input(const std::string& path, const PatternArgs& a, double tolerance, bool speed_used) {
  check_trace_options_apply(a, path);
  PatternOptions o;
  o.speed_used = speed_used;
  o.machine_file = a.machine;
  o.tolerance = tolerance;
  if (!a.speed.empty()) o.speed = option_quantity(a.speed, dim::speed, "--speed");
  o.trace = trace_options(a);
  return load_job_or_pattern(path, o);
}

}  // namespace polarcam::cli
