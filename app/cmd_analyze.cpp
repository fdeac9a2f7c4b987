// polarcam analyze JOB.toml [--json] [--csv FILE] [--plot FILE] [--speed Q]... [--mass Q]... [--depth Q]...
// The dynamics of a job (docs/dynamics.md): torques both motors need along the path, their pull-out torques, the
// torque ratios, and the verdict. Exit status 0 GO, 1 NO-GO, 2 bad input.
#include <iostream>
#include <nlohmann/json.hpp>

#include "report/analysis_report.hpp"
#include "app/cli.hpp"
#include "io/progress.hpp"
#include "io/output.hpp"
#include "cam/error.hpp"
#include "cam/units.hpp"

namespace polarcam::cli {
namespace cmd_analyze {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string job, csv, plot, spacing;
  PatternArgs pattern;
  bool json = false, quiet = false;
  std::vector<std::string> speeds, masses, depths;
  SafetyFactor safety_factor;
};

std::vector<double> quantities(const std::vector<std::string>& texts, const Dim& d, const char* option) {
  std::vector<double> v;
  for (const auto& t : texts) {
    try {
      v.push_back(parse_quantity_as(t, d));
    } catch (const InputError& e) {
      throw InputError(std::string(option) + ": " + e.what());
    }
    if (!(v.back() > 0.0) && d != dim::mass) throw InputError(std::string(option) + " " + t + ": must be positive");
    if (!(v.back() >= 0.0)) throw InputError(std::string(option) + " " + t + ": must be zero or positive");
  }
  return v;
}

int run(const Opts& o) {
  // every output checked before any work
  if (!o.csv.empty()) check_output_path(o.csv);
  if (!o.plot.empty()) plot::check_plot_path(o.plot);
  PatternArgs pattern = o.pattern;
  if (!o.speeds.empty()) pattern.speed = o.speeds.front();  // a pattern is analysed at the first --speed
  Job job = load_job_input(o.job, pattern);
  apply_safety_factor(o.safety_factor, job);
  const auto speeds = quantities(o.speeds, dim::speed, "--speed");
  const auto masses = quantities(o.masses, dim::mass, "--mass");
  const auto depths = quantities(o.depths, dim::length, "--depth");
  if (!masses.empty() && !depths.empty()) throw InputError("give --mass or --depth, not both");
  if (!depths.empty() && job.load.kind != LoadKind::grinding)
    throw InputError("--depth needs a job whose [load] is kind = \"grinding\"", job.file);

  AnalysisOptions opt;
  if (!o.spacing.empty()) {
    opt.spacing = option_quantity(o.spacing, dim::length, "--spacing");
    if (!(opt.spacing > 0.0)) throw InputError("must be a positive length", "--spacing");
  }
  // the cases: speeds x loads
  std::vector<LoadSpec> loads;
  for (double m : masses) {
    LoadSpec l;
    l.kind = LoadKind::inertial;
    l.mass = m;
    loads.push_back(l);
  }
  for (double d : depths) {
    LoadSpec l = job.load;
    l.grinding.depth = d;
    loads.push_back(l);
  }
  if (loads.empty()) loads.push_back(job.load);
  std::vector<std::optional<double>> vs;
  for (double v : speeds) vs.push_back(v);
  if (vs.empty()) vs.push_back(std::nullopt);

  const PreparedDynamics prep = prepare_dynamics(job);
  std::vector<CaseResult> cases;
  const bool keep = !o.csv.empty() || !o.plot.empty();
  opt.keep_series = keep;
  {
    TerminalBar bar("analyze", o.quiet);  // erased before the output
    const Progress progress = bar.callback();
    const double n = static_cast<double>(vs.size() * loads.size());
    for (const auto& v : vs)
      for (const auto& l : loads) {
        const double k = static_cast<double>(cases.size());
        cases.push_back(analyze_case(job, prep, DynamicsCase{v, l}, opt, true, progress_part(progress, k / n, (k + 1) / n)));
      }
  }

  std::vector<std::pair<std::string, std::string>> files;
  if (!o.csv.empty()) files.emplace_back(o.csv, series_csv(job, cases));
  if (!o.plot.empty()) files.emplace_back(o.plot, plot::render(torque_ratio_figure(job, cases), plot::plot_format(o.plot)));
  write_files_atomic(files);

  bool all_go = true;
  for (const auto& c : cases) all_go = all_go && c.verdict.go;
  const std::string side = prep.side > 0 ? "left" : "right";
  if (o.json) {
    nlohmann::ordered_json j;
    j["job"] = job.file;
    j["contour"] = job.contour->name();
    j["machine"] = job.machine.name;
    j["tool_side"] = side;
    if (cases.size() == 1) {
      const nlohmann::ordered_json one = case_json(job, cases.front());
      for (auto it = one.begin(); it != one.end(); ++it) j[it.key()] = it.value();
    } else {
      j["verdict"] = all_go ? "GO" : "NO-GO";
      for (const auto& c : cases) j["cases"].push_back(case_json(job, c));
    }
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "polarcam analyze " << job.file << "\n";
    std::cout << "  contour    " << job.contour->name() << (job.contour->closed() ? " (closed)" : " (open)")
              << ", tool centre " << side << " of the travel\n";
    std::cout << "  machine    " << (job.machine.name.empty() ? "(unnamed)" : job.machine.name) << "\n";
    std::cout << "  motors     radial: " << job.machine.dynamics->radial.describe() << "\n";
    std::cout << "             angular: " << job.machine.dynamics->angular.describe() << "\n";
    for (size_t k = 0; k < cases.size(); ++k) {
      if (cases.size() > 1) std::cout << "  case " << k + 1 << " of " << cases.size() << "\n";
      std::cout << case_text(job, cases[k]);
    }
  }
  return all_go ? 0 : 1;
}

}  // namespace cmd_analyze

void register_analyze(CLI::App& app, Action& action) {
  using namespace cmd_analyze;
  auto o = std::make_shared<Opts>();
  CLI::App* c =
      app.add_subcommand("analyze",
                         "Torques, pull-out torques and torque ratios of both axes along a job's path, and GO / NO-GO "
                         "(exit status 0 GO, 1 NO-GO, 2 bad input)");
  c->add_option("job", o->job, "job file (TOML) whose machine has dynamics")->required();
  add_pattern_options(c, o->pattern, false);
  c->add_flag("--json", o->json, "print the result as one JSON object");
  c->add_flag("--quiet", o->quiet, "no progress bar (shown on a terminal only)");
  c->add_option("--csv", o->csv, "write the series along the path to this CSV file");
  c->add_option("--plot", o->plot, "draw the torque-ratio plots (Figures 5.8-5.25) to this .png or .svg file");
  c->add_option("--speed", o->speeds, "analyse at this speed instead of the job's (repeatable), e.g. \"0.51 cm/s\"");
  c->add_option("--mass", o->masses,
                "analyse with an inertial load of this mass instead of the job's load (repeatable)");
  c->add_option("--depth", o->depths, "grinding jobs: analyse at this depth of cut instead of the job's (repeatable)");
  c->add_option("--spacing", o->spacing, "largest distance between samples along the path, e.g. \"0.1 mm\"");
  add_safety_factor_option(c, o->safety_factor);
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
