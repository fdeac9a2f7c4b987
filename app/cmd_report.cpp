// polarcam report JOB.toml -o report.html [--map-size N] [--max-evaluations N] [--threads N] [--safety-factor X]
// The operator's report (docs/operator-report.md): one self-contained HTML page with the verdict and its fix, the
// contour on the work area, the tape, the accuracy, the torques, the capacity and the pole study.
#include <filesystem>
#include <iostream>

#include "app/cli.hpp"
#include "io/progress.hpp"
#include "report/operator_report.hpp"
#include "report/pattern_report.hpp"
#include "io/output.hpp"
#include "cam/error.hpp"

namespace polarcam::cli {
namespace cmd_report {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string job, output;
  PatternArgs pattern;
  StudyOptions report;
  SafetyFactor safety_factor;
  bool quiet = false;
  CLI::Option *map_size_opt = nullptr, *evaluations_opt = nullptr;  // the job report's survey and searches
};

int run(const Opts& o) {
  check_output_path(o.output);
  check_output_extension(o.output, {".html", ".htm"}, "the report");
  Job job = load_job_input(o.job, o.pattern);
  apply_safety_factor(o.safety_factor, job);
  // a machine without dynamics, or a sand table's coupled arm: the report of what it will draw, which has no pole
  // survey, no searches and no torque ratios for their options to set
  if (pattern_report_applies(job)) {
    const char* why = "the report of a machine without dynamics (or with a coupled arm) has no pole survey, pole "
                      "search or torque ratios for it to set";
    if (option_given(o.map_size_opt)) throw InputError(why, "--map-size");
    if (option_given(o.evaluations_opt)) throw InputError(why, "--max-evaluations");
    if (option_given(o.safety_factor.option)) throw InputError(why, "--safety-factor");
  }
  const OperatorReport r = [&] {
    TerminalBar bar("report", o.quiet);  // erased before the output
    if (pattern_report_applies(job)) return pattern_report(job, study_pattern(job));
    return operator_report(job, study_job(job, o.report, bar.callback()));
  }();
  write_file_atomic(o.output, r.html);
  std::cout << (r.go ? "GO" : "NO-GO") << ": report written to " << o.output << "\n";
  return r.go ? 0 : 1;
}

}  // namespace cmd_report

void register_report(CLI::App& app, Action& action) {
  using namespace cmd_report;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("report", "The operator's report: one self-contained HTML page to read before "
                                             "running a job (verdict, accuracy, torques, capacity, placement)");
  c->add_option("job", o->job, "job file (TOML) or pattern; a machine without dynamics or with a coupled arm gets the pattern report")->required();
  add_pattern_options(c, o->pattern);
  c->add_option("-o,--output", o->output, "the report (.html)")->required();
  o->map_size_opt = c->add_option("--map-size", o->report.map_size, "poles per side of the pole survey (default 31)")
      ->check(CLI::Range(4, 201));
  o->evaluations_opt = c->add_option("--max-evaluations", o->report.max_evaluations,
                "budget of each pole search (default: as polarcam optimize)")
      ->check(CLI::Range(10, 10000000));
  c->add_option("--threads", o->report.threads, "threads (default: all cores; the report does not depend on it)")
      ->check(CLI::Range(0, 1024));
  add_safety_factor_option(c, o->safety_factor);
  c->add_flag("--quiet", o->quiet, "no progress bar (shown on a terminal only)");
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
