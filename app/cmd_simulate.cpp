// polarcam simulate ac|bands CONFIG [--json] [--csv [FILE]] [--plot FIG]
//   ac:    Elbestawi's A/C loop [--strategy A|B|none] [--spindle-stiffness Q] [--cutting-stiffness Q] [--nominal-force Q]
//   bands: Fussell & Gagne's band controller [--step FRACTION] [--axial-depth Q]
// Exit status 1 when the simulation exceeds a limit: the A/C file's [limit] force, or a tool's limit for the bands.
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "io/output.hpp"
#include "job/tool_file.hpp"
#include "process/limits.hpp"
#include "process/sim_file.hpp"
#include "report/simulate_report.hpp"

namespace polarcam::cli {
namespace cmd_simulate {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string kind, file, plot, csv;
  std::string strategy, spindle_stiffness, cutting_stiffness, nominal_force;  // ac
  std::string step, axial_depth;                                             // bands
  bool json = false, csv_given = false;
};

// An option's InputError from a settings check names section.key: name the option instead.
[[noreturn]] void rethrow_as_option(const InputError& e, const std::vector<std::pair<std::string, std::string>>& keys,
                                    const std::string& file) {
  for (const auto& [key, option] : keys)
    if (e.place() == key) throw InputError(e.message(), option);
  throw InputError(e.message(), file + ": key '" + e.place() + "'");
}

int run(const Opts& o) {
  const bool csv_stdout = o.csv_given && (o.csv.empty() || o.csv == "-");
  if (csv_stdout && o.json) throw InputError("prints the series on standard output, as --json would: give --csv a file", "--csv");
  if (!o.plot.empty()) plot::check_plot_path(o.plot);
  if (o.csv_given && !csv_stdout) check_output_path(o.csv);
  const bool ac = o.kind == "ac";
  if (ac) {
    for (const auto& [v, opt] : {std::pair{o.step, "--step"}, std::pair{o.axial_depth, "--axial-depth"}})
      if (!v.empty()) throw InputError("is an option of `simulate bands`", opt);
  } else {
    for (const auto& [v, opt] : {std::pair{o.strategy, "--strategy"}, std::pair{o.spindle_stiffness, "--spindle-stiffness"},
                                 std::pair{o.cutting_stiffness, "--cutting-stiffness"}, std::pair{o.nominal_force, "--nominal-force"}})
      if (!v.empty()) throw InputError("is an option of `simulate ac`", opt);
  }

  std::string csv, text;
  nlohmann::ordered_json j;
  std::optional<plot::Figure> fig;
  bool exceeded = false;
  if (ac) {
    AcReport r;
    r.problem = process::read_ac_file(o.file);
    process::AcLoopSettings& s = r.problem.settings;
    const Dim stiffness = dim::force / dim::length;
    if (!o.strategy.empty()) {
      if (o.strategy == "A") s.strategy = process::ImpactStrategy::A;
      else if (o.strategy == "B") s.strategy = process::ImpactStrategy::B;
      else if (o.strategy == "none") s.strategy = process::ImpactStrategy::none;
      else throw InputError("must be A, B or none", "--strategy");
    }
    if (!o.spindle_stiffness.empty()) s.spindle_stiffness = option_quantity(o.spindle_stiffness, stiffness, "--spindle-stiffness");
    if (!o.cutting_stiffness.empty()) s.cutting_stiffness = option_quantity(o.cutting_stiffness, stiffness, "--cutting-stiffness");
    if (!o.nominal_force.empty()) s.F_nom = option_quantity(o.nominal_force, dim::force, "--nominal-force");
    try {
      process::check(s);
    } catch (const InputError& e) {
      rethrow_as_option(e, {{"cut.spindle_stiffness", "--spindle-stiffness"}, {"cut.cutting_stiffness", "--cutting-stiffness"},
                            {"control.F_nom", "--nominal-force"}}, o.file);
    }
    r.result = process::simulate_ac_loop(s);
    if (auto e = process::eq521_of(s)) r.poles = process::closed_loop_poles(*e);
    r.limit_exceeded = r.problem.force_limit && r.result.peak_force > *r.problem.force_limit;
    exceeded = r.limit_exceeded;
    if (o.csv_given) csv = ac_csv(r.result);
    if (!o.plot.empty()) fig = ac_figure(r);
    if (o.json) j = ac_json(r);
    else text = ac_text(r);
  } else {
    BandReport r;
    r.problem = process::read_band_file(o.file);
    process::BandSettings& s = r.problem.settings;
    if (!o.step.empty()) s.step_fraction = option_quantity(o.step, dim::none, "--step");
    if (!o.axial_depth.empty()) s.cut.axial_depth = option_quantity(o.axial_depth, dim::length, "--axial-depth");
    if (r.problem.tool_file) {
      const process::ToolLimits l = process::tool_limits(load_tool_file(*r.problem.tool_file));
      try {
        process::apply_tool_limits(s, l);
      } catch (const InputError& e) {
        throw InputError(e.message() + " (the tool " + *r.problem.tool_file + ")", o.file + ": key '" + e.place() + "'");
      }
    }
    try {
      process::check(s);
    } catch (const InputError& e) {
      rethrow_as_option(e, {{"controller.step", "--step"}, {"cut.axial_depth", "--axial-depth"}}, o.file);
    }
    r.result = process::simulate_band_control(s);
    r.limit_exceeded = !r.result.exceeded.empty();
    exceeded = r.limit_exceeded;
    if (o.csv_given) csv = band_csv(r);
    if (!o.plot.empty()) fig = band_figure(r);
    if (o.json) j = band_json(r);
    else text = band_text(r);
  }

  std::vector<std::pair<std::string, std::string>> files;
  if (fig) files.emplace_back(o.plot, plot::render(*fig, plot::plot_format(o.plot)));
  if (o.csv_given && !csv_stdout) files.emplace_back(o.csv, csv);
  write_files_atomic(files);
  if (csv_stdout) {
    std::cout << csv;
  } else if (o.json) {
    if (!o.plot.empty()) j["plot"] = o.plot;
    if (o.csv_given) j["csv"] = o.csv;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << text;
    if (!o.plot.empty()) std::cout << "  figure " << o.plot << "\n";
    if (o.csv_given) std::cout << "  series " << o.csv << "\n";
  }
  return exceeded ? 1 : 0;
}

}  // namespace cmd_simulate

void register_simulate(CLI::App& app, Action& action) {
  using namespace cmd_simulate;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "simulate", "Simulate feed control of a milling cut: `ac`, the adaptive-control loop with its impact "
                  "strategies (Elbestawi 1980); `bands`, the event-band controller (Fussell & Gagne 1991). Exit "
                  "status 1 when a limit is exceeded");
  c->add_option("kind", o->kind, "ac or bands")->required()->check(CLI::IsMember({"ac", "bands"}));
  c->add_option("config", o->file, "the simulation file (TOML, docs/process.md)")->required();
  c->add_flag("--json", o->json, "print the results as one JSON object");
  CLI::Option* csv = c->add_option("--csv", o->csv, "the time series: to this file, or without one on standard output")
                         ->expected(0, 1);
  c->add_option("--plot", o->plot, "draw the time series to this .png or .svg file");
  c->add_option("--strategy", o->strategy, "ac: the impact strategy instead of the file's (A, B or none)");
  c->add_option("--spindle-stiffness", o->spindle_stiffness, "ac: K_S instead of the file's (\"7030 N/mm\")");
  c->add_option("--cutting-stiffness", o->cutting_stiffness, "ac: K_C instead of the file's (\"8970 N/mm\")");
  c->add_option("--nominal-force", o->nominal_force, "ac: F_nom instead of the file's (\"1320 N\")");
  c->add_option("--step", o->step, "bands: the step, a fraction of the programmed feed, instead of the file's (0.01)");
  c->add_option("--axial-depth", o->axial_depth, "bands: the axial depth instead of the file's (\"0.25 in\")");
  c->callback([o, csv, &action] {
    o->csv_given = csv->count() > 0;
    action = [o] { return run(*o); };
  });
}

}  // namespace polarcam::cli
