// polarcam motor fit POINTS.csv [--machine FILE --axis radial|angular] [--supply-voltage Q] [--resistance Q]
//                               [--rotor-teeth N] [--energisation S] [--loss cauchy|huber|none] [--json] ...
// Fits the electrical pull-out model (Eq. 5.17, App. F) to a measured pull-out curve (machine/dynamics/motor_fit.hpp).
#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "job/job_dynamics.hpp"
#include "io/output.hpp"
#include "report/plot.hpp"
#include "cam/error.hpp"
#include "cam/point_files.hpp"
#include "cam/units.hpp"
#include "machine/dynamics/motor_fit.hpp"

namespace polarcam::cli {
namespace cmd_motor {  // named, not anonymous: the command files are compiled together (unity build)

struct FitOpts {
  std::string points, machine, axis = "radial", voltage, resistance, energisation, rate_unit = "Hz",
                               torque_unit = "N m", loss = "cauchy", loss_scale, plot, csv;
  int rotor_teeth = 0;
  bool json = false;
};

double unit_of(const std::string& text, const Dim& d, const char* option) {
  try {
    return parse_quantity_as("1 " + text, d);
  } catch (const InputError& e) {
    throw InputError(std::string(option) + ": " + e.what());
  }
}

double quantity(const std::string& text, const Dim& d, const char* option) {
  try {
    return parse_quantity_as(text, d);
  } catch (const InputError& e) {
    throw InputError(std::string(option) + ": " + e.what());
  }
}

std::string g(double v, int prec = 6) { return fmt::format("{:.{}g}", v, prec); }
std::string pm(const std::optional<double>& sd) { return sd ? " +- " + g(*sd, 2) : " (not determined)"; }

int fit(const FitOpts& o) {
  // every output checked before any work
  if (!o.csv.empty()) check_output_path(o.csv);
  if (!o.plot.empty()) plot::check_plot_path(o.plot);
  ElectricalMotor known;
  if (!o.machine.empty()) {
    if (o.axis != "radial" && o.axis != "angular") throw InputError("--axis must be radial or angular");
    MachineModel m = load_machine_dynamics(o.machine);
    const StepperMotor& sm = o.axis == "radial" ? m.radial : m.angular;
    if (!sm.electrical())
      throw InputError("the " + o.axis + " motor is a pull-out curve, not an electrical model", o.machine);
    known = std::get<ElectricalMotor>(sm.model);
  }
  if (!o.voltage.empty()) {
    known.supply_voltage = quantity(o.voltage, dim::voltage, "--supply-voltage");
    if (!(known.supply_voltage > 0.0)) throw InputError("must be a positive voltage", "--supply-voltage");
  }
  if (!o.resistance.empty()) {
    known.R_a = quantity(o.resistance, dim::resistance, "--resistance");
    if (!(known.R_a > 0.0)) throw InputError("must be a positive resistance", "--resistance");
  }
  if (o.rotor_teeth != 0) known.rotor_teeth = o.rotor_teeth;
  if (!o.energisation.empty()) {
    auto e = parse_energisation(o.energisation);
    if (!e) throw InputError("--energisation must be wave, full_one or full_two");
    known.energisation = *e;
  }
  if (!(known.supply_voltage > 0.0)) throw InputError("give --supply-voltage (or --machine)");
  if (!(known.R_a > 0.0)) throw InputError("give --resistance, the winding and drive resistance (or --machine)");
  if (known.rotor_teeth <= 0) throw InputError("give --rotor-teeth (or --machine)");

  MotorFitOptions fo;
  auto loss = parse_robust_loss(o.loss);
  if (!loss) throw InputError("--loss must be cauchy, huber or none");
  fo.loss = *loss;
  if (!o.loss_scale.empty()) {
    if (fo.loss == RobustLoss::none)
      throw InputError("scales a robust loss (cauchy or huber); --loss none fits plain least squares", "--loss-scale");
    fo.loss_scale = quantity(o.loss_scale, dim::torque, "--loss-scale");
  }

  const double ru = unit_of(o.rate_unit, dim::frequency, "--rate-unit");
  const double tu = unit_of(o.torque_unit, dim::torque, "--torque-unit");
  std::vector<PulloutPoint> pts;
  for (Vec2 p : read_points_csv(o.points, 1.0)) pts.push_back({p.x * ru, p.y * tu});
  const MotorFitResult r = in_file(o.points, [&] { return fit_electrical_motor(pts, known, fo); });
  const ElectricalMotor& m = r.motor;
  double fmax = 0.0;
  for (const auto& p : pts) fmax = std::max(fmax, p.rate_hz);
  std::vector<std::pair<double, double>> curve;
  for (int i = 0; i <= 100; ++i) {
    const double f = fmax * i / 100.0;
    curve.emplace_back(f, m.pullout_at_rate(f));
  }
  const std::string toml = fmt::format(
      "[machine.motor]\nmodel = \"electrical\"\nenergisation = \"{}\"\nsupply_voltage = \"{} V\"\n"
      "torque_constant = \"{} N m/A\"\nvoltage_constant = \"{} V s/rad\"\nrotor_teeth = {}\nresistance = \"{} ohm\"\n"
      "inductance = \"{} H\"\n",
      to_string(m.energisation), g(m.supply_voltage), g(m.K_T), g(m.K_V), m.rotor_teeth, g(m.R_a), g(m.L_a));

  std::vector<std::pair<std::string, std::string>> files;
  if (!o.csv.empty()) {
    std::string s = "rate_hz,torque_Nm\n";
    for (const auto& [f, t] : curve) s += fmt::format("{:.10g},{:.10g}\n", f, t);
    files.emplace_back(o.csv, s);
  }
  if (!o.plot.empty()) {
    plot::Figure fig = plot::figure(900, 600);
    plot::Panel p = plot::panel("Pull-out torque: measured points and the fitted model (Eq. 5.17)",
                                "step rate (Hz)",
                                "pull-out torque (N m)");
    plot::Series in, out, model;
    for (size_t i = 0; i < pts.size(); ++i) {
      plot::Series& s = r.outlier[i] ? out : in;
      s.x.push_back(pts[i].rate_hz);
      s.y.push_back(pts[i].torque);
    }
    for (const auto& [f, t] : curve) {
      model.x.push_back(f);
      model.y.push_back(t);
    }
    model.label = "fitted model";
    in.width = out.width = 0;
    in.marker = 4;
    out.marker = 2;
    in.marker_scale = out.marker_scale = 1.3;
    in.label = "measured";
    out.label = "outliers";
    out.color = plot::palette(1);
    model.color = plot::palette(6);
    p.series.push_back(model);
    p.series.push_back(in);
    if (!out.x.empty()) p.series.push_back(out);
    p.ymin = 0.0;
    fig.panels.push_back(p);
    files.emplace_back(o.plot, plot::render(fig, plot::plot_format(o.plot)));
  }
  write_files_atomic(files);

  if (o.json) {
    nlohmann::ordered_json j;
    j["points_file"] = o.points;
    j["points"] = pts.size();
    j["known"] = {{"supply_voltage_V", m.supply_voltage}, {"resistance_ohm", m.R_a},
                  {"rotor_teeth", m.rotor_teeth},         {"energisation", to_string(m.energisation)},
                  {"steps_per_rev", m.steps_per_rev()},   {"pullout_coefficient", pullout_coefficient(m.energisation)}};
    auto sd = [](const std::optional<double>& v) {
      return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr);
    };
    j["fitted"] = {{"torque_constant_NmpA", m.K_T},
                   {"torque_constant_sd", sd(r.K_T_sd)},
                   {"voltage_constant_Vsprad", m.K_V},
                   {"voltage_constant_sd", sd(r.K_V_sd)},
                   {"inductance_H", m.L_a},
                   {"inductance_sd", sd(r.L_a_sd)}};
    j["loss"] = to_string(r.loss);
    j["loss_scale_Nm"] = r.loss_scale;
    j["rms_residual_Nm"] = r.rms;
    j["max_abs_residual_Nm"] = r.max_abs_residual;
    nlohmann::ordered_json outl = nlohmann::ordered_json::array();
    for (size_t i = 0; i < pts.size(); ++i)
      if (r.outlier[i]) outl.push_back(i + 1);
    j["outliers"] = outl;
    j["converged"] = r.converged;
    j["iterations"] = r.iterations;
    j["initial_cost"] = r.initial_cost;
    j["final_cost"] = r.final_cost;
    j["solver"] = r.report;
    for (size_t i = 0; i < pts.size(); ++i)
      j["residuals"].push_back({{"rate_hz", pts[i].rate_hz},
                                {"torque_Nm", pts[i].torque},
                                {"model_Nm", pts[i].torque + r.residuals[i]},
                                {"residual_Nm", r.residuals[i]},
                                {"outlier", static_cast<bool>(r.outlier[i])}});
    for (const auto& [f, t] : curve) j["curve"].push_back({{"rate_hz", f}, {"torque_Nm", t}});
    j["machine_toml"] = toml;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "polarcam motor fit " << o.points << " (" << pts.size() << " points)\n";
    std::cout << "  known      " << g(m.supply_voltage) << " V, R_a " << g(m.R_a) << " ohm, N_s " << m.rotor_teeth
              << ", " << to_string(m.energisation) << " (" << g(m.steps_per_rev()) << " steps/rev, c_p "
              << g(pullout_coefficient(m.energisation)) << ")\n";
    std::cout << "  fitted     K_T " << g(m.K_T) << pm(r.K_T_sd) << " N m/A, K_V " << g(m.K_V) << pm(r.K_V_sd)
              << " V s/rad, L_a " << g(m.L_a) << pm(r.L_a_sd) << " H\n";
    std::cout << "  residuals  rms " << g(r.rms, 4) << " N m, max " << g(r.max_abs_residual, 4)
              << " N m over the inliers; " << to_string(r.loss) << " loss, scale " << g(r.loss_scale, 3) << " N m\n";
    size_t nout = 0;
    for (size_t i = 0; i < pts.size(); ++i)
      if (r.outlier[i]) {
        std::cout << "  outlier    point " << i + 1 << ": " << g(pts[i].rate_hz) << " Hz, " << g(pts[i].torque)
                  << " N m (model " << g(pts[i].torque + r.residuals[i]) << " N m)\n";
        ++nout;
      }
    std::cout << "  solver     " << r.report << "\n";
    std::cout << "  for the machine file:\n";
    std::string line;
    for (char ch : toml) {
      if (ch == '\n') {
        std::cout << "    " << line << "\n";
        line.clear();
      } else {
        line += ch;
      }
    }
  }
  return 0;
}

}  // namespace cmd_motor

void register_motor(CLI::App& app, Action& action) {
  using namespace cmd_motor;
  CLI::App* motor = app.add_subcommand("motor", "Stepping-motor models");
  motor->require_subcommand(1);
  auto o = std::make_shared<FitOpts>();
  CLI::App* c = motor->add_subcommand(
      "fit", "Fit the electrical pull-out model (Eq. 5.17) to measured pull-out points: rate,torque per CSV line");
  c->add_option("points", o->points, "CSV file: step rate, pull-out torque per line (header and # comments allowed)")
      ->required();
  CLI::Option* machine = c->add_option("--machine", o->machine,
                "machine file whose motor gives the known constants (voltage, R_a, N_s, scheme)");
  c->add_option("--axis", o->axis, "which motor of --machine: radial (default) or angular")->needs(machine);
  c->add_option("--supply-voltage", o->voltage, "supply voltage, e.g. \"24 V\"");
  c->add_option("--resistance", o->resistance, "winding plus drive resistance, e.g. \"6.5 ohm\"");
  c->add_option("--rotor-teeth", o->rotor_teeth, "rotor teeth N_s (50 for a 200-step motor)")->check(CLI::Range(1, 100000));
  c->add_option("--energisation", o->energisation, "wave (half step, default), full_one or full_two (Table F.1)");
  c->add_option("--rate-unit", o->rate_unit, "unit of the rate column (default Hz: motor steps per second as driven)");
  c->add_option("--torque-unit", o->torque_unit,
                "unit of the torque column (default \"N m\"; e.g. \"ozf in\", \"N cm\")");
  c->add_option("--loss", o->loss, "robust loss: cauchy (default), huber or none");
  c->add_option("--loss-scale", o->loss_scale, "loss scale as a torque (default from the data's spread)");
  c->add_option("--plot", o->plot, "draw the points and the fitted curve to this .png or .svg file");
  c->add_option("--csv", o->csv, "write the fitted curve (rate_hz,torque_Nm) to this CSV file");
  c->add_flag("--json", o->json, "print the result as one JSON object");
  c->callback([o, &action] { action = [o] { return fit(*o); }; });
}

}  // namespace polarcam::cli
