// polarcam capacity JOB.toml [--json] [--speed Q] [--safety-factor X] [--curve N] [--csv FILE] [--plot FILE]
// The largest speed and the largest load (added mass, depth of cut or tool force) at which the job's worst torque
// ratio reaches 1 / safety factor (Sec. 6.6.2, docs/optimum-loading.md), and the capacity curve.
#include <filesystem>
#include <iostream>

#include "report/capacity_report.hpp"
#include "app/cli.hpp"
#include "io/output.hpp"
#include "cam/error.hpp"
#include "cam/units.hpp"

namespace polarcam::cli {
namespace cmd_capacity {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string job, speed, csv, plot;
  PatternArgs pattern;
  bool json = false;
  SafetyFactor safety_factor;
  int curve = 0;
};

int run(const Opts& o) {
  // every output checked before any work
  if (!o.csv.empty()) check_output_path(o.csv);
  if (!o.plot.empty()) plot::check_plot_path(o.plot);
  PatternArgs pattern = o.pattern;
  pattern.speed = o.speed;  // a pattern's speed is the --speed of the question
  Job job = load_job_input(o.job, pattern);
  apply_safety_factor(o.safety_factor, job);
  std::optional<double> at_speed;
  if (!o.speed.empty()) {
    try {
      at_speed = parse_quantity_as(o.speed, dim::speed);
    } catch (const InputError& e) {
      throw InputError(std::string("--speed: ") + e.what());
    }
  }
  int points = o.curve;
  if (points == 0 && (!o.csv.empty() || !o.plot.empty())) points = 12;
  if (points > 0 && load_measure(job.load) == LoadMeasure::none)
    throw InputError("a capacity curve needs a [load] (inertial, grinding or force)", job.file);
  const PreparedDynamics prep = prepare_dynamics(job);
  const JobCapacity c = job_capacity(job, prep, at_speed, points);
  std::vector<std::pair<std::string, std::string>> files;
  if (!o.csv.empty()) files.emplace_back(o.csv, capacity_csv(job, c));
  if (!o.plot.empty()) files.emplace_back(o.plot, plot::render(capacity_figure(job, c), plot::plot_format(o.plot)));
  write_files_atomic(files);
  if (o.json)
    std::cout << capacity_json(job, c).dump(2) << "\n";
  else
    std::cout << capacity_text(job, c);
  return 0;
}

}  // namespace cmd_capacity

void register_capacity(CLI::App& app, Action& action) {
  using namespace cmd_capacity;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "capacity", "The largest speed and the largest load (mass, depth of cut or tool force) at which a job's worst "
                  "torque ratio reaches 1 / safety factor");
  c->add_option("job", o->job, "job file (TOML) whose machine has dynamics")->required();
  add_pattern_options(c, o->pattern, false);
  c->add_flag("--json", o->json, "print the result as one JSON object");
  c->add_option("--speed", o->speed, "find the largest load at this speed instead of the job's, e.g. \"1 cm/s\"");
  add_safety_factor_option(c, o->safety_factor);
  c->add_option("--curve", o->curve, "the largest load at this many speeds, up to the speed at which a motor reaches its top step rate")
      ->check(CLI::Range(2, 200));
  c->add_option("--csv", o->csv, "write the capacity curve as CSV (12 speeds unless --curve)");
  c->add_option("--plot", o->plot, "draw the capacity curve (.png or .svg)");
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
