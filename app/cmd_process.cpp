// polarcam process JOB.toml [--json] [--csv FILE] [--plot FILE.svg|png]
// The milling cut of a job along its tool path (docs/process.md): the constant-force schedule of a constant-force
// job (or the job's own speed), the feed per tooth, the mean and peak forces, what binds the feed on each stretch,
// the tool's limits and the time. Exit status 0, or 1 when the job's own speed takes a force or the feed per tooth
// above a tool's limit (a constant-force schedule never does).
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "io/output.hpp"
#include "report/process_report.hpp"

namespace polarcam::cli {
namespace cmd_process {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string job, csv, plot;
  bool json = false;
};

int run(const Opts& o) {
  if (!o.csv.empty()) check_output_path(o.csv);
  if (!o.plot.empty()) plot::check_plot_path(o.plot);
  const Job job = load_job_input(o.job, PatternArgs{});
  const ProcessRun r = run_process(job);
  std::vector<std::pair<std::string, std::string>> files;
  if (!o.plot.empty()) files.emplace_back(o.plot, plot::render(process_figure(r), plot::plot_format(o.plot)));
  if (!o.csv.empty()) files.emplace_back(o.csv, process_csv(r));
  write_files_atomic(files);
  if (o.json) {
    nlohmann::ordered_json j;
    j["job"] = job.file;
    const nlohmann::ordered_json p = process_json(job, r);
    for (auto it = p.begin(); it != p.end(); ++it) j[it.key()] = it.value();
    if (!o.csv.empty()) j["csv"] = o.csv;
    if (!o.plot.empty()) j["plot"] = o.plot;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << process_text(job, r);
    if (!o.csv.empty()) std::cout << "  series " << o.csv << "\n";
    if (!o.plot.empty()) std::cout << "  figure " << o.plot << "\n";
  }
  return r.exceeded.empty() ? 0 : 1;
}

}  // namespace cmd_process

void register_process(CLI::App& app, Action& action) {
  using namespace cmd_process;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "process",
      "The milling cut of a job ([load] kind = \"milling\"): forces, feed per tooth and what binds the feed along "
      "the path, the constant-force schedule of speed_profile = \"constant-force\", the time. Exit status 1 when "
      "the job's speed exceeds a tool's limit");
  c->add_option("job", o->job, "job file (TOML) with a milling load")->required();
  c->add_flag("--json", o->json, "print the result as one JSON object");
  c->add_option("--csv", o->csv, "write the series along the path (s, t, speed, feed per tooth, forces, binding)");
  c->add_option("--plot", o->plot, "draw the force and the feed along the path to this .svg or .png file");
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
