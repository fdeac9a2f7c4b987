// polarcam cut-force --teeth Z --spindle-speed N --radial-depth A --axial-depth B [--axial-depth B2 ...]
//                    (--force F --feed-per-tooth F_T | --specific-force K3) [--feed-speed V] [--json]
// The lumped cutting-force model F = C v(t - tau), C = K b a (Elbestawi 1980, Sec. 4.4; process/cutting_force.hpp).
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "cam/format.hpp"
#include "process/cutting_force.hpp"

namespace polarcam::cli {
namespace cmd_cut_force {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  int teeth = 0;
  std::string spindle, radial, force, feed_per_tooth, specific, feed_speed;
  std::vector<std::string> axial;
  bool json = false;
};

int run(const Opts& o) {
  const double omega = option_quantity(o.spindle, dim::angular_speed, "--spindle-speed");
  if (!(omega > 0.0)) throw InputError("must be a positive speed, e.g. \"500 rpm\"", "--spindle-speed");
  const double a = option_quantity(o.radial, dim::length, "--radial-depth");
  if (!(a > 0.0)) throw InputError("must be a positive length", "--radial-depth");
  std::vector<double> b;
  for (const std::string& s : o.axial) {
    b.push_back(option_quantity(s, dim::length, "--axial-depth"));
    if (!(b.back() > 0.0)) throw InputError("must be a positive length", "--axial-depth");
  }
  const double tau = process::tooth_period(o.teeth, omega);
  std::optional<double> ft;
  if (!o.feed_per_tooth.empty()) {
    ft = option_quantity(o.feed_per_tooth, dim::length, "--feed-per-tooth");
    if (!(*ft > 0.0)) throw InputError("must be a positive length", "--feed-per-tooth");
  }
  process::LumpedForceModel m;
  if (!o.force.empty() == !o.specific.empty())
    throw InputError("give either --force with --feed-per-tooth (K from a cut) or --specific-force", "--force");
  if (!o.force.empty()) {
    if (!ft) throw InputError("--force needs --feed-per-tooth (the cut the force was measured at)", "--force");
    const double F = option_quantity(o.force, dim::force, "--force");
    if (!(F > 0.0)) throw InputError("must be a positive force", "--force");
    m = process::calibrate_lumped_model(F, *ft, b.front(), a, tau);
  } else {
    const double k = option_quantity(o.specific, dim::force / (dim::length * dim::area), "--specific-force");
    if (!(k > 0.0)) throw InputError("must be positive, e.g. \"205 N/mm^3\"", "--specific-force");
    m = process::lumped_model_from_specific_force(k, tau);
  }
  if (o.force.empty() && ft && !o.feed_speed.empty())
    throw InputError("and --feed-speed both give the feed of the forces: give one (--feed-per-tooth sets the feed "
                     "speed f_t / tau; with --force it is the cut the force was measured at)",
                     "--feed-per-tooth");
  double v = 0.0;
  if (!o.feed_speed.empty()) {
    v = option_quantity(o.feed_speed, dim::speed, "--feed-speed");
    if (!(v >= 0.0)) throw InputError("must be zero or a positive speed", "--feed-speed");
  } else if (ft) {
    v = *ft / tau;
  } else {
    throw InputError("give --feed-speed or --feed-per-tooth (the feed the forces are for)", "--feed-speed");
  }
  const std::vector<double> F = process::lumped_forces(m, b, a, v);

  // K in N/mm^2 per mm/s, C in N per mm/s: the thesis's units
  if (o.json) {
    nlohmann::ordered_json j;
    j["teeth"] = o.teeth;
    j["spindle_speed_rpm"] = omega * 60.0 / (2.0 * 3.14159265358979323846);
    j["radial_depth_mm"] = a * 1e3;
    j["axial_depths_mm"] = nlohmann::ordered_json::array();
    for (double x : b) j["axial_depths_mm"].push_back(x * 1e3);
    j["tau_s"] = tau;
    j["feed_speed_mm_per_s"] = v * 1e3;
    j["K_N_per_mm2_per_mm_per_s"] = m.K * 1e-9;
    j["C_N_per_mm_per_s"] = nlohmann::ordered_json::array();
    for (double x : b) j["C_N_per_mm_per_s"].push_back(m.C(x, a) * 1e-3);
    j["forces_N"] = F;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::ostringstream os;
  os << "lumped cutting force F = C v(t - tau), C = K b a (Elbestawi Sec. 4.4)\n"
     << "  tooth period tau      " << significant(tau, 6) << " s\n"
     << "  feed speed v          " << significant(v * 1e3, 6) << " mm/s\n"
     << "  K                     " << significant(m.K * 1e-9, 6) << " N/mm^2/(mm/s)\n";
  for (size_t i = 0; i < b.size(); ++i)
    os << "  b = " << significant(b[i] * 1e3, 6) << " mm: C = " << significant(m.C(b[i], a) * 1e-3, 6)
       << " N/(mm/s), F = " << significant(F[i], 6) << " N\n";
  std::cout << os.str();
  return 0;
}

}  // namespace cmd_cut_force

void register_cut_force(CLI::App& app, Action& action) {
  using namespace cmd_cut_force;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "cut-force", "The lumped cutting-force model F = C v(t - tau), C = K b a (Elbestawi Sec. 4.4): K from one cut, "
                   "or from a specific force; the force at a feed for each axial depth");
  c->add_option("--teeth", o->teeth, "number of teeth z")->required()->check(CLI::Range(1, 100));
  c->add_option("--spindle-speed", o->spindle, "spindle speed, e.g. \"500 rpm\" (tau = 1/(z N))")->required();
  c->add_option("--radial-depth", o->radial, "radial depth of cut a, e.g. \"20 mm\"")->required();
  c->add_option("--axial-depth", o->axial, "axial depth of cut b (repeat for several; the first calibrates)")
      ->required();
  c->add_option("--force", o->force, "the force measured or estimated at --feed-per-tooth and the first depth");
  c->add_option("--feed-per-tooth", o->feed_per_tooth, "feed per tooth f_t, e.g. \"0.1 mm\" (v = f_t / tau)");
  c->add_option("--specific-force", o->specific, "k of F = k a b (x(t) - x(t - tau)), e.g. \"205 N/mm^3\"");
  c->add_option("--feed-speed", o->feed_speed, "the feed speed the forces are for, e.g. \"12.7 mm/s\"");
  c->add_flag("--json", o->json, "print as one JSON object (units in the keys)");
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
