// polarcam servo JOB|TAPE|--path square|diamond|circle --drives DRIVES.toml [--feed Q] [--ramp Q] [--integral C_I]
//                [--tolerance Q] [--json] [--csv FILE] [--plot FILE]
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "digitizer/tape_file.hpp"
#include "cam/error.hpp"
#include "cam/units.hpp"
#include "io/output.hpp"
#include "machine/servo/contour.hpp"
#include "machine/servo/drives_file.hpp"
#include "machine/servo/step_reference.hpp"
#include "pipeline/servo_case.hpp"
#include "report/servo_report.hpp"

namespace polarcam::cli {
namespace cmd_servo {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string input, path, drives, feed, ramp, tolerance, csv, plot, corner;
  double integral = 0.0;
  CLI::Option* integral_option = nullptr;  // whether --integral was given: every value of it is checked
  bool integral_given() const { return option_given(integral_option); }
  bool json = false, report_model = false;
};

int run_report_model(const Opts& o) {
  if (!o.input.empty() || !o.path.empty() || !o.csv.empty() || !o.plot.empty() || !o.feed.empty() || !o.ramp.empty() ||
      !o.tolerance.empty())
    throw InputError("reports the drives' model alone: give only --drives (and --json, --integral)", "--report-model");
  servo::Drives d = servo::read_drives_file(o.drives);
  servo::ModelReport r[2];
  for (int i = 0; i < 2; ++i) {
    if (o.integral_given()) d.axis[i].params.C_I = o.integral;
    try {
      r[i] = servo::model_report(d.axis[i].params);
    } catch (const InputError& e) {
      throw InputError(e.message(), o.integral_given() ? "--integral" : o.drives);
    }
  }
  if (o.json)
    std::cout << servo_model_json(d, r).dump(2) << "\n";
  else
    std::cout << servo_model_text(d, r);
  return 0;
}

int run(const Opts& o) {
  if (o.integral_given() && !(o.integral >= 0.0 && o.integral < 1e6)) throw InputError("must be from 0 to 1e6 (1/s)", "--integral");
  if (o.report_model) return run_report_model(o);
  if (o.input.empty() == o.path.empty()) throw InputError("give a job or a tape, or --path (one of them)", "--path");
  if (!o.path.empty()) servo::parse_test_path(o.path);
  if (o.path.empty() && !o.feed.empty()) throw InputError("sets the speed of a --path (a job or tape has its own)", "--feed");
  if (o.path.empty() && !o.ramp.empty()) throw InputError("ramps a --path (a job or tape has its own speeds)", "--ramp");
  if (!o.corner.empty() && o.corner != "sharp" && o.corner != "spline" && o.corner != "spline2")
    throw InputError("'" + o.corner + "' is not a corner: give sharp, spline (one segment) or spline2 (two)", "--corner");
  const bool splined = o.corner == "spline" || o.corner == "spline2";
  if (splined && o.path.empty()) throw InputError("blends the corners of a --path (square or diamond)", "--corner");
  if (splined && !o.ramp.empty()) throw InputError("give --ramp or a spline --corner, not both", "--corner");
  servo::ServoOptions so;
  if (!o.tolerance.empty()) {
    so.tolerance = option_quantity(o.tolerance, dim::length, "--tolerance");
    if (!(so.tolerance > 0.0)) throw InputError("must be a positive length", "--tolerance");
  }

  if (!o.plot.empty()) plot::check_plot_path(o.plot);
  if (!o.csv.empty()) check_output_path(o.csv);

  ServoAnalysis a;
  a.drives_file = o.drives;
  a.drives = servo::read_drives_file(o.drives);
  if (o.integral_given()) {
    for (auto& ax : a.drives.axis) ax.params.C_I = o.integral;
    try {
      for (auto& ax : a.drives.axis) servo::check(ax.params);
    } catch (const InputError& e) {
      throw InputError(e.message(), "--integral");
    }
  }
  const double T = a.drives.axis[0].params.T;
  servo::Reference ref;
  if (!o.path.empty()) {
    if (a.drives.polar) throw InputError("the test paths are Cartesian: give drives with [x] and [y]", o.drives);
    const double feed = o.feed.empty() ? 20e-3 : option_quantity(o.feed, dim::speed, "--feed");
    const double ramp = o.ramp.empty() ? 0.0 : option_quantity(o.ramp, dim::time, "--ramp");
    if (splined) {
      // J. Peng's blend: 1 mm on each axis of the diamond's corner, sqrt(2) mm along its legs (Sec. 4.4.3)
      servo::SplinedPath sp = servo::test_path_with_splines(servo::parse_test_path(o.path), feed, T,
                                                            o.corner == "spline" ? 1 : 2, std::sqrt(2.0) * 1e-3);
      ref = std::move(sp.reference);
      a.corners = std::move(sp.corners);
    } else {
      ref = servo::test_path(servo::parse_test_path(o.path), feed, T, ramp);
    }
    a.input = "path " + o.path + " at " + significant(feed * 1e3, 6) + " mm/s" +
              (ramp > 0.0 ? ", ramps of " + significant(ramp, 6) + " s" : "") +
              (splined ? ", corners blended by " + o.corner : "");
  } else if (is_tape_file(o.input)) {
    ref = servo::reference_from_tape(o.input, a.drives.polar, T);
    a.input = "tape " + o.input;
    a.staircase = true;
  } else {
    if (!a.drives.polar) throw InputError("a job is digitized for a polar machine: give drives with [r] and [theta]", o.drives);
    ref = job_servo_reference(load_job_input(o.input, PatternArgs{}), T);
    a.input = "job " + o.input;
    a.staircase = true;
  }
  a.result = servo::run_contour(a.drives, ref, so);

  std::vector<std::pair<std::string, std::string>> files;
  if (!o.plot.empty()) files.emplace_back(o.plot, plot::render(servo_figure(a), plot::plot_format(o.plot)));
  if (!o.csv.empty()) files.emplace_back(o.csv, servo_csv(a));
  write_files_atomic(files);
  if (o.json) {
    nlohmann::ordered_json j = servo_json(a);
    if (!o.plot.empty()) j["plot"] = o.plot;
    if (!o.csv.empty()) j["csv"] = o.csv;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << servo_text(a);
  }
  return a.result.within_tolerance() ? 0 : 1;
}

}  // namespace cmd_servo

void register_servo(CLI::App& app, Action& action) {
  using namespace cmd_servo;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "servo", "Servo feed drives: each axis's following error and the contour error of a job, a tape or a test "
               "path, against a tolerance (J. Peng 1989); exit status 1 when the path leaves the tolerance");
  c->add_option("input", o->input, "job file (polar drives) or step tape (.tape: polar or Cartesian)");
  c->add_option("--path", o->path, "a test path instead: square, diamond or circle (Cartesian drives)");
  c->add_option("--drives", o->drives, "the drives file ([x] and [y], or [r] and [theta]; docs/feed-drives.md)")->required();
  c->add_option("--feed", o->feed, "the test path's speed along the path (default 20 mm/s)");
  c->add_option("--ramp", o->ramp, "linear speed ramps of this duration at each leg's ends (\"0.1 s\")");
  c->add_option("--corner", o->corner, "the test path's corners: sharp (default), spline (one cubic segment) or "
                                       "spline2 (two), over 1.41 mm each side (Sec. 4.4.3)");
  o->integral_option =
      c->add_option("--integral", o->integral, "integral action C_I (1/s) in both position loops (Eq. 4.107; 0.5 in the thesis)");
  c->add_option("--tolerance", o->tolerance, "contour error allowed (default 0.05 mm)");
  c->add_flag("--json", o->json, "print the results as one JSON object");
  c->add_flag("--report-model", o->report_model, "print each axis's model instead: velocity loop, discrete G, "
                                                  "following error per speed, yield per cutting torque, current "
                                                  "sensor bandwidth");
  c->add_option("--csv", o->csv, "write t_s, reference and actual positions and the contour error to this file");
  c->add_option("--plot", o->plot, "draw the path and the contour error to this .png or .svg file");
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
