// polarcam identify RESPONSE.csv [--json] [--forgetting LAMBDA]
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "cam/format.hpp"
#include "process/identify.hpp"

namespace polarcam::cli {
namespace cmd_identify {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string file;
  double forgetting = 1.0;
  bool json = false;
  CLI::Option* forgetting_opt = nullptr;
};

nlohmann::ordered_json model_json(const process::DiscreteModel& d, const process::SecondOrder& s) {
  return {{"A1", d.A1},           {"A2", d.A2}, {"B1", d.B1}, {"B2", d.B2}, {"omega_n_rad_s", s.omega_n},
          {"zeta", s.zeta},       {"gain_m_per_N", s.gain}};
}

int run(const Opts& o) {
  if (!(o.forgetting > 0.0 && o.forgetting <= 1.0)) throw InputError("must be in (0, 1]", "--forgetting");
  const process::Response r = process::read_response_csv(o.file);
  const auto dec = process::log_decrement(r.displacement, r.period);
  std::optional<process::DiscreteModel> batch, rls;
  std::optional<process::SecondOrder> sb, sr;
  if (r.force.empty() && option_given(o.forgetting_opt))
    throw InputError("weights the recursive least squares, which need a force_N column; " + o.file +
                         " has none (its free response gives the logarithmic decrement only)",
                     "--forgetting");
  if (!r.force.empty()) {
    batch = process::batch_least_squares(r.force, r.displacement);
    sb = in_file(o.file, [&] { return process::to_second_order(*batch, r.period); });
    process::RlsOptions ro;
    ro.forgetting = o.forgetting;
    rls = process::recursive_least_squares(r.force, r.displacement, ro);
    sr = in_file(o.file, [&] { return process::to_second_order(*rls, r.period); });
  }
  if (!dec && !batch)
    throw InputError("no force_N column for least squares, and fewer than three peaks for the logarithmic decrement",
                     o.file);
  if (o.json) {
    nlohmann::ordered_json j;
    j["samples"] = r.displacement.size();
    j["sample_period_s"] = r.period;
    if (dec)
      j["log_decrement"] = {{"delta", dec->delta},         {"zeta", dec->zeta}, {"omega_n_rad_s", dec->omega_n},
                            {"omega_d_rad_s", dec->omega_d}, {"peaks", dec->peaks}};
    else
      j["log_decrement"] = nullptr;
    j["least_squares"] = batch ? model_json(*batch, *sb) : nlohmann::ordered_json();
    if (rls) {
      j["recursive_least_squares"] = model_json(*rls, *sr);
      j["recursive_least_squares"]["forgetting"] = o.forgetting;
    } else {
      j["recursive_least_squares"] = nullptr;
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::ostringstream os;
  os << r.displacement.size() << " samples every " << significant(r.period, 6) << " s\n";
  if (dec)
    os << "  logarithmic decrement over " << dec->peaks << " peaks: delta " << significant(dec->delta, 5) << ", zeta "
       << significant(dec->zeta, 5) << ", w_n " << significant(dec->omega_n, 6) << " rad/s\n";
  auto line = [&](const char* what, const process::DiscreteModel& d, const process::SecondOrder& s) {
    os << "  " << what << ": A1 " << significant(d.A1, 6) << ", A2 " << significant(d.A2, 6) << ", B1 "
       << significant(d.B1, 8) << ", B2 " << significant(d.B2, 8) << "\n    w_n " << significant(s.omega_n, 6)
       << " rad/s, zeta " << significant(s.zeta, 5) << ", static gain K " << significant(s.gain, 6) << " m/N\n";
  };
  if (batch) line("batch least squares", *batch, *sb);
  if (rls) line(("recursive least squares (forgetting " + significant(o.forgetting, 6) + ")").c_str(), *rls, *sr);
  std::cout << os.str();
  return 0;
}

}  // namespace cmd_identify

void register_identify(CLI::App& app, Action& action) {
  using namespace cmd_identify;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "identify", "A second-order structure from a measured response: logarithmic decrement, batch and recursive "
                  "least squares of the discrete model, w_n, zeta and static gain (Dunckley 1978, Ch. 4)");
  c->add_option("response", o->file, "CSV with t_s, displacement_m and (for least squares) force_N")->required();
  c->add_flag("--json", o->json, "print the results as one JSON object");
  o->forgetting_opt = c->add_option("--forgetting", o->forgetting, "forgetting factor of the recursive estimate, in (0, 1] (default 1)");
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
