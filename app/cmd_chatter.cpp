// polarcam chatter STRUCTURE.toml [--json] [--lobes] [--spindle-min Q --spindle-max Q --lobe-count N]
//                                 [--plot FIG] [--simulate K_c [--duration Q] [--csv [FILE]]
//                                 [--suppress [--steps-out FILE]]]
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "cam/units.hpp"
#include "io/output.hpp"
#include "process/chatter_file.hpp"
#include "report/chatter_report.hpp"

namespace polarcam::cli {
namespace cmd_chatter {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string file, plot, spindle_min, spindle_max, simulate, duration, csv, steps_out;
  int lobe_count = 400;
  bool json = false, lobes = false, csv_given = false, suppress = false;
  CLI::Option* lobe_count_opt = nullptr;
};

// A spindle speed: a frequency ("5 Hz", rev/s) or an angular speed ("300 rpm"); in rev/s.
double spindle_speed(const std::string& text, const std::string& option) {
  Quantity q;
  try {
    q = parse_quantity(text);
  } catch (const InputError& e) {
    throw InputError(e.message(), option);
  }
  double n = 0.0;
  if (q.dim == dim::frequency)
    n = q.value;
  else if (q.dim == dim::angular_speed)
    n = q.value / (2.0 * 3.14159265358979323846);
  else
    throw InputError("must be a spindle speed, e.g. \"300 rpm\" or \"5 Hz\"", option);
  if (!(n > 0.0 && n < 1e7)) throw InputError("must be a positive spindle speed below 1e7 rev/s", option);
  return n;
}

// The cutting gain: a plain number (N/m) or a stiffness with units ("4.2 kN/m").
double cutting_gain(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (!text.empty() && end && *end == '\0') return v;
  return option_quantity(text, dim::mass / (dim::time * dim::time), "--simulate");
}

int run(const Opts& o) {
  // every option checked before any work
  const bool csv_stdout = o.csv_given && (o.csv.empty() || o.csv == "-");
  if (o.csv_given && o.simulate.empty()) throw InputError("needs --simulate K_c (the series it writes)", "--csv");
  if (csv_stdout && o.json) throw InputError("prints the series on standard output, as --json would: give --csv a file", "--csv");
  if (!o.duration.empty() && o.simulate.empty()) throw InputError("needs --simulate K_c", "--duration");
  if (o.suppress && o.simulate.empty()) throw InputError("needs --simulate K_c (the cut it suppresses)", "--suppress");
  if (!o.steps_out.empty() && !o.suppress) throw InputError("needs --suppress (the steps it writes)", "--steps-out");
  if (!o.steps_out.empty()) check_output_path(o.steps_out);
  if (o.lobe_count < 2 || o.lobe_count > 20000) throw InputError("must be from 2 to 20000", "--lobe-count");
  // the lobes' range and count shape the table of --lobes and the figure of --plot, nothing else
  if (!o.lobes && o.plot.empty()) {
    const char* why = "shapes the stability lobes: give --lobes (the table) or --plot FILE (the figure) with it";
    if (!o.spindle_min.empty()) throw InputError(why, "--spindle-min");
    if (!o.spindle_max.empty()) throw InputError(why, "--spindle-max");
    if (option_given(o.lobe_count_opt)) throw InputError(why, "--lobe-count");
  }
  if (!o.plot.empty()) plot::check_plot_path(o.plot);
  if (o.csv_given && !csv_stdout) check_output_path(o.csv);
  ChatterAnalysis a;
  a.problem = process::read_chatter_file(o.file);
  const process::Cut& cut = a.problem.cut;
  if (o.suppress && !a.problem.suppressor)
    throw InputError("has no [suppressor] table (sample_period, step_size, max_step_rate, model): --suppress needs one",
                     o.file);
  process::SpeedRange range = process::default_lobe_range(cut);
  if (!o.spindle_min.empty()) range.n_min = spindle_speed(o.spindle_min, "--spindle-min");
  if (!o.spindle_max.empty()) range.n_max = spindle_speed(o.spindle_max, "--spindle-max");
  if (!(range.n_max > range.n_min)) throw InputError("must be above --spindle-min", "--spindle-max");
  process::SimulationOptions so;
  if (!o.simulate.empty()) {
    a.simulated_gain = cutting_gain(o.simulate);
    if (!(std::isfinite(*a.simulated_gain) && *a.simulated_gain >= 0.0))
      throw InputError("must be a cutting gain of 0 or more (N/m)", "--simulate");
    if (!o.duration.empty()) {
      so.duration = option_quantity(o.duration, dim::time, "--duration");
      if (!(so.duration >= cut.revolution_period))
        throw InputError("must be at least one revolution period", "--duration");
    }
  }

  const process::TransferFunction g = process::workpiece_compliance(a.problem.structure);
  a.modes = process::modes(g);
  a.nyquist = process::nyquist_limit(g, cut.overlap, cut.revolution_period);
  a.simple = process::simple_criterion(g, cut.overlap);
  if (o.lobes || !o.plot.empty()) a.lobes = process::stability_lobes(g, cut.overlap, range.n_min, range.n_max, o.lobe_count);
  if (a.simulated_gain && o.suppress) {
    a.suppression = process::simulate_suppression(a.problem.structure, cut, *a.simulated_gain, *a.problem.suppressor, so);
    a.simulation = a.suppression->without;
  } else if (a.simulated_gain) {
    a.simulation = process::simulate_chatter(a.problem.structure, cut, *a.simulated_gain, so);
  }
  // the series written: the suppressed run's (with the tool's displacement) under --suppress
  auto series = [&a] { return a.suppression ? suppression_csv(a.suppression->with) : simulation_csv(*a.simulation); };

  std::vector<std::pair<std::string, std::string>> files;
  if (!o.plot.empty()) files.emplace_back(o.plot, plot::render(chatter_lobes_figure(a), plot::plot_format(o.plot)));
  if (o.csv_given && !csv_stdout) files.emplace_back(o.csv, series());
  if (!o.steps_out.empty()) files.emplace_back(o.steps_out, steps_csv(*a.suppression));
  write_files_atomic(files);
  if (csv_stdout) {
    std::cout << series();
    return 0;
  }
  if (!o.lobes && !o.plot.empty()) a.lobes.clear();  // the table only when asked
  if (o.json) {
    nlohmann::ordered_json j = chatter_json(a);
    if (!o.plot.empty()) j["plot"] = o.plot;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << chatter_text(a);
    if (!o.plot.empty()) std::cout << "  figure " << o.plot << "\n";
  }
  return 0;
}

}  // namespace cmd_chatter

void register_chatter(CLI::App& app, Action& action) {
  using namespace cmd_chatter;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "chatter", "Regenerative chatter of a two-mass machine-workpiece structure: the limiting cutting gain and the "
                 "chatter frequency (Nyquist and the simple criterion), stability lobes, time-domain simulation "
                 "(Dunckley 1978)");
  c->add_option("structure", o->file, "the structure file ([structure] and [cut], docs/chatter.md)")->required();
  c->add_flag("--json", o->json, "print the results as one JSON object");
  c->add_flag("--lobes", o->lobes, "add the table of the limit over spindle speed");
  c->add_option("--spindle-min", o->spindle_min, "lowest spindle speed of the lobes (\"150 rpm\"; default half the cut's)");
  c->add_option("--spindle-max", o->spindle_max, "highest spindle speed of the lobes (default twice the cut's)");
  o->lobe_count_opt = c->add_option("--lobe-count", o->lobe_count, "spindle speeds in the lobe table (default 400)");
  c->add_option("--plot", o->plot, "draw the stability lobes to this .png or .svg file");
  c->add_option("--simulate", o->simulate, "simulate the cut in time at this cutting gain K_c (N/m)");
  c->add_option("--duration", o->duration, "simulated time (default 40 revolutions)");
  c->add_flag("--suppress", o->suppress,
              "simulate the cut also with the stepper chatter suppressor of the file's [suppressor] table (Dunckley "
              "1978, Ch. 3 and Sec. 5.4); needs --simulate");
  c->add_option("--steps-out", o->steps_out, "with --suppress: the positioner's steps t_s,dir,position_steps to this CSV file");
  CLI::Option* csv = c->add_option("--csv", o->csv, "the simulated series t_s,x_m_m,x_w_m,force_N (with --suppress: "
                                                    "t_s,x_m_m,x_w_m,x_t_m,force_N of the suppressed cut): to this "
                                                    "file, or without one on standard output")
                         ->expected(0, 1);
  c->callback([o, csv, &action] {
    o->csv_given = csv->count() > 0;
    action = [o] { return run(*o); };
  });
}

}  // namespace polarcam::cli
