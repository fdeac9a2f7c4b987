#pragma once
// Subcommands of the polarcam executable. Each registers itself on the CLI11 app and, when chosen, stores the
// action to run in `action`; main() runs it and maps errors to exit codes (InputError -> 2).
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "cam/image_trace.hpp"
#include "cam/units.hpp"
#include "job/job.hpp"

namespace polarcam::cli {

using Action = std::function<int()>;

// --machine and --speed: what makes a pattern file (.thr, .svg, .dxf, .csv) a job (job/pattern.hpp).
// Whether an option was given on the command line (a default value, or 0, is not "not given"); false for none.
inline bool option_given(const CLI::Option* opt) { return opt != nullptr && opt->count() > 0; }

struct PatternArgs {
  std::string machine, speed;
  std::string pixel_size;  // an image's tracing (cam/image_trace.hpp)
  double threshold = 0.5;
  bool invert = false;
  int despeckle = 2;
  // the tracing options as registered (add_trace_options), to tell whether one was given
  CLI::Option* trace_given[4] = {nullptr, nullptr, nullptr, nullptr};
};
// with_speed false: the command has a --speed of its own, which the caller copies into a.speed.
void add_pattern_options(CLI::App* c, PatternArgs& a, bool with_speed = true);
// --pixel-size, --threshold, --invert, --despeckle: how an image is traced.
void add_trace_options(CLI::App* c, PatternArgs& a);
// The tracing options they give; InputError naming the option that is wrong.
TraceOptions trace_options(const PatternArgs& a);
// InputError naming the option when a tracing option was given but `input` is not an image (.png, .pbm, .pgm):
// it would be silently ignored. load_job_input checks it.
void check_trace_options_apply(const PatternArgs& a, const std::string& input);
// One warning line on stderr for each motor that the job's steps would drive above its max_step_rate (the tape is
// still made: a slower replay may run it).
void warn_step_rate_excess(const Job& job, const DigitizeResult& r);
// The job file or pattern `path` with the pattern options; a bad --speed is an InputError naming it.
// `tolerance` (m): how close a drawing's joined contours stay to their curves (job/pattern.hpp).
// `speed_used` false: the command's result does not depend on the speed (PatternOptions::speed_used).
Job load_job_input(const std::string& path, const PatternArgs& a, double tolerance = 1e-4, bool speed_used = true);
// The quantity an option gives ("0.1 mm"), of dimension d; InputError naming the option otherwise.
double option_quantity(const std::string& text, const Dim& d, const std::string& option);

// --safety-factor, instead of the job's [limits]: its value and whether it was given at all (a value such as 0 must
// be refused, not taken for "not given").
struct SafetyFactor {
  double value = 0.0;
  CLI::Option* option = nullptr;
};
void add_safety_factor_option(CLI::App* c, SafetyFactor& sf);
// Sets job.safety_factor when the option was given; InputError naming it unless it is at least 1.
void apply_safety_factor(const SafetyFactor& sf, Job& job);

// Adds one subcommand to `app`; when it is chosen, stores what to run in `action`.
using Register = void(CLI::App& app, Action& action);
Register register_digitize, register_inspect, register_dda, register_play, register_controller_sim, register_error,
    register_optimize, register_optimize_speed, register_analyze, register_motor, register_compare, register_capacity,
    register_report, register_check, register_preview, register_export, register_trace, register_template_speed,
    register_capture, register_chatter, register_identify, register_limits, register_cut_force, register_monitor,
    register_simulate, register_servo;
Register register_process;

// The subcommands, in the order `polarcam --help` lists them.
inline constexpr Register* kCommands[] = {
    register_digitize, register_inspect, register_dda, register_play, register_controller_sim, register_error,
    register_optimize, register_optimize_speed, register_analyze, register_motor, register_compare, register_capacity,
    register_report, register_check, register_preview, register_export, register_trace, register_template_speed,
    register_capture, register_chatter, register_identify, register_limits, register_cut_force, register_monitor,
    register_simulate, register_servo,
    register_process};

}  // namespace polarcam::cli
