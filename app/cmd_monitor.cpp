// polarcam monitor SIGNAL.csv --spindle N --teeth Z [--signal COLUMN | --estimate-force] [--json] ...
// polarcam monitor --generate OUT.csv --spindle N --teeth Z [--break-at T] [--chatter-at T ...]
#include <cstdlib>
#include <iostream>
#include <vector>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <sstream>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "cam/format.hpp"
#include "io/output.hpp"
#include "process/milling_signal.hpp"
#include "process/monitor.hpp"
#include "process/signal_file.hpp"

namespace polarcam::cli {
namespace cmd_monitor {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string file, spindle, signal, friction = "0.196 N m s/rad", rule = "peng";
  int teeth = 0;
  bool json = false, estimate = false, no_chatter = false;
  std::optional<double> threshold, threshold_factor, learn;
  std::string chatter_setpoint, overload;
  // the generator
  std::string generate, duration = "6 s", rate = "500 Hz", peak_force = "500 N", noise = "10 N", break_at,
                        chatter_at, chatter_frequency, chatter_force = "300 N";
  double runout = 0.1, engagement = 0.0;
  int broken_tooth = 0;
  uint64_t seed = 1;
};

// A level in the signal's unit: a quantity of its dimension, or a plain number for a column of another unit.
double level(const std::string& text, const std::string& quantity, const std::string& option) {
  if (quantity == "force") return option_quantity(text, dim::force, option);
  if (quantity == "current") return option_quantity(text, dim::current, option);
  return option_quantity(text, dim::none, option);
}

int generate(const Opts& o, double rev_per_s) {
  process::MillingSignalOptions g;
  g.duration_s = option_quantity(o.duration, dim::time, "--duration");
  g.sample_rate_hz = option_quantity(o.rate, dim::frequency, "--rate");
  g.spindle_rev_per_s = rev_per_s;
  g.teeth = o.teeth;
  g.engagement = o.engagement > 0.0 ? o.engagement : 1.0 / o.teeth;
  g.peak_force_N = option_quantity(o.peak_force, dim::force, "--peak-force");
  g.runout = o.runout;
  g.noise_N = option_quantity(o.noise, dim::force, "--noise");
  g.seed = o.seed;
  if (!o.break_at.empty()) g.break_at_s = option_quantity(o.break_at, dim::time, "--break-at");
  g.broken_tooth = o.broken_tooth;
  if (!o.chatter_at.empty()) {
    g.chatter_at_s = option_quantity(o.chatter_at, dim::time, "--chatter-at");
    if (o.chatter_frequency.empty()) throw InputError("--chatter-at needs a frequency, e.g. \"173 Hz\"", "--chatter-frequency");
    g.chatter_frequency_hz = option_quantity(o.chatter_frequency, dim::frequency, "--chatter-frequency");
    g.chatter_force_N = option_quantity(o.chatter_force, dim::force, "--chatter-force");
  }
  const auto r = process::milling_force_signal(g);
  check_output_path(o.generate);
  write_file_atomic(o.generate, process::format_signal_csv(r));
  std::cerr << "wrote " << r.samples() << " samples of force_N (" << significant(g.duration_s, 6) << " s at "
            << significant(g.sample_rate_hz, 6) << " Hz) to " << o.generate << "\n";
  return 0;
}

int run(const Opts& o) {
  const double omega = option_quantity(o.spindle, dim::angular_speed, "--spindle");
  if (!(omega > 0.0)) throw InputError("must be a positive speed, e.g. \"600 rpm\"", "--spindle");
  const double rev_per_s = omega / (2.0 * std::numbers::pi);
  if (!o.generate.empty()) {
    if (!o.file.empty()) throw InputError("--generate writes a signal: give no signal file to read", "--generate");
    return generate(o, rev_per_s);
  }
  if (o.file.empty()) throw InputError("give a signal file (CSV: time_s, then the signal columns)", "SIGNAL");
  const auto record = process::read_signal_csv(o.file);
  const double friction =
      option_quantity(o.friction, dim::torque * dim::time / dim::angle, "--friction");
  const auto s = process::select_signal(record, o.file, o.signal, o.estimate, friction);

  process::MonitorOptions m;
  m.sample_rate_hz = s.sample_rate_hz;
  m.spindle_rev_per_s = rev_per_s;
  m.teeth = o.teeth;
  if (o.rule == "fussell")
    m.rule = process::BreakageRule::fussell;
  else if (o.rule != "peng")
    throw InputError("must be peng or fussell", "--rule");
  if (o.threshold) m.threshold = *o.threshold;
  if (o.threshold_factor) m.threshold_factor = *o.threshold_factor;
  if (o.learn) m.learn_revolutions = *o.learn;
  m.chatter = !o.no_chatter;
  if (!o.chatter_setpoint.empty()) m.chatter_setpoint = level(o.chatter_setpoint, s.quantity, "--chatter-setpoint");
  if (!o.overload.empty()) m.overload = level(o.overload, s.quantity, "--overload");
  const auto r = in_file(o.file, [&] { return process::monitor_signal(s.x, m); });

  const std::string unit = s.quantity == "force" ? "N" : s.quantity == "current" ? "A" : "";
  if (o.json) {
    nlohmann::ordered_json j;
    j["file"] = o.file;
    j["signal"] = s.name;
    j["samples"] = s.x.size();
    j["sample_rate_hz"] = s.sample_rate_hz;
    j["spindle_rpm"] = rev_per_s * 60.0;
    j["teeth"] = o.teeth;
    j["tooth_frequency_hz"] = r.tooth_frequency_hz;
    j["samples_per_tooth"] = r.samples_per_tooth;
    j["tooth_periods"] = r.tooth_periods;
    j["breakage"] = {{"rule", o.rule},
                     {"threshold", r.breakage_threshold},
                     {"threshold_given", o.threshold.has_value()},
                     {"learned_max_normalised_difference", r.learned_max_normalised},
                     {"learn_end_s", s.start_s + r.learn_end_s}};
    if (m.chatter)
      j["chatter"] = {{"setpoint", r.chatter_setpoint}, {"block_s", r.chatter_block_s}, {"blocks", r.chatter_blocks}};
    else
      j["chatter"] = nullptr;
    j["events"] = nlohmann::ordered_json::array();
    for (const auto& e : r.events) {
      nlohmann::ordered_json ej{{"kind", process::to_string(e.kind)}, {"time_s", s.start_s + e.time_s},
                                {"end_s", s.start_s + e.end_s},        {"value", e.value},
                                {"threshold", e.threshold},            {"count", e.count}};
      if (e.kind == process::EventKind::chatter) ej["frequency_hz"] = e.frequency_hz;
      j["events"].push_back(ej);
    }
    j["verdict"] = r.events.empty() ? "GO" : "NO-GO";
    std::cout << j.dump(2) << "\n";
    return r.events.empty() ? 0 : 1;
  }
  std::ostringstream os;
  os << o.file << ": " << s.name << ", " << s.x.size() << " samples at " << significant(s.sample_rate_hz, 6)
     << " Hz; " << significant(rev_per_s * 60.0, 6) << " rpm, " << o.teeth << " teeth: tooth frequency "
     << significant(r.tooth_frequency_hz, 6) << " Hz, " << significant(r.samples_per_tooth, 6)
     << " samples per tooth period, " << r.tooth_periods << " periods\n";
  os << "  breakage (" << (o.rule == "peng" ? "Peng Eq. 3.69" : "Fussell & Gagne Eq. 1-3")
     << "): |normalised difference| over " << significant(r.breakage_threshold, 4)
     << (o.threshold ? " (given)" : " (learned: " + significant(r.learned_max_normalised, 4) + " in the first " +
                                        significant(s.start_s + r.learn_end_s, 4) + " s)")
     << "\n";
  if (m.chatter) {
    if (r.chatter_setpoint > 0.0)
      os << "  chatter (Fussell & Gagne Eq. 22-24): amplitude over " << significant(r.chatter_setpoint, 5) << " "
         << unit << " and a PSD peak off the spindle harmonics, " << r.chatter_blocks << " blocks of "
         << significant(r.chatter_block_s, 4) << " s\n";
    else
      os << "  chatter: not checked (the record is shorter than two blocks of " << significant(r.chatter_block_s, 4)
         << " s)\n";
  }
  if (r.events.empty()) os << "no event: GO\n";
  for (const auto& e : r.events) {
    os << "  " << process::to_string(e.kind) << " at " << significant(s.start_s + e.time_s, 6) << " s: "
       << significant(e.value, 5) << (e.kind == process::EventKind::breakage ? "" : " " + unit) << " over "
       << significant(e.threshold, 5) << (e.kind == process::EventKind::breakage ? "" : " " + unit);
    if (e.kind == process::EventKind::chatter) os << ", at " << significant(e.frequency_hz, 5) << " Hz";
    if (e.count > 1)
      os << " (" << e.count << (e.kind == process::EventKind::chatter ? " blocks" : " tooth periods") << " to "
         << significant(s.start_s + e.end_s, 6) << " s)";
    os << "\n";
  }
  if (!r.events.empty()) os << r.events.size() << " event" << (r.events.size() > 1 ? "s" : "") << ": NO-GO\n";
  std::cout << os.str();
  return r.events.empty() ? 0 : 1;
}

}  // namespace cmd_monitor

void register_monitor(CLI::App& app, Action& action) {
  using namespace cmd_monitor;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "monitor", "Tool breakage, chatter and overload from a recorded force or feed-motor current (Peng 1989, Sec. "
                 "3.2-3.5; Fussell & Gagne 1991, Eq. 1-3, 22-24): exit status 1 when an event is found");
  c->add_option("signal", o->file, "CSV: time_s, then signal columns such as force_N, current_A, speed_rad_per_s");
  c->add_option("--spindle", o->spindle, "spindle speed, e.g. \"600 rpm\"")->required();
  c->add_option("--teeth", o->teeth, "number of teeth of the cutter")->required()->check(CLI::Range(1, 100));
  std::vector<CLI::Option*> reading, generated;  // the options of reading a signal, of --generate
  reading.push_back(c->add_option("--signal", o->signal, "the column to watch (default force_N, else current_A, else the first)"));
  CLI::Option* estimate = c->add_flag("--estimate-force", o->estimate,
              "watch the feeding force estimated from current_A and speed_rad_per_s (Peng Eq. 3.40)");
  reading.push_back(estimate);
  CLI::Option* friction = c->add_option("--friction", o->friction, "the drive's viscous friction B for --estimate-force (default "
                                           "\"0.196 N m s/rad\", Peng Sec. 3.2)");
  friction->needs(estimate);
  reading.push_back(friction);
  reading.push_back(c->add_option("--rule", o->rule, "breakage rule: peng (normalised first difference) or fussell (and the second "
                                   "difference larger than the first)"));
  CLI::Option* threshold = c->add_option("--threshold", o->threshold, "breakage threshold on the normalised difference (default: learned)");
  reading.push_back(threshold);
  CLI::Option* factor = c->add_option("--threshold-factor", o->threshold_factor,
                "learned threshold = this times the largest normalised difference of the learning revolutions (3)");
  factor->excludes(threshold);  // a threshold given is not learned
  reading.push_back(factor);
  reading.push_back(c->add_option("--learn-revolutions", o->learn, "revolutions at the start taken as a clean cut (3)"));
  CLI::Option* setpoint = c->add_option("--chatter-setpoint", o->chatter_setpoint,
                "chatter amplitude set point in the signal's unit, e.g. \"250 N\" (default: 1.2 times the first "
                "block's)");
  reading.push_back(setpoint);
  CLI::Option* no_chatter = c->add_flag("--no-chatter", o->no_chatter, "do not check for chatter");
  setpoint->excludes(no_chatter);
  reading.push_back(no_chatter);
  reading.push_back(c->add_option("--overload", o->overload, "report tooth-period means above this, e.g. \"900 N\""));
  reading.push_back(c->add_flag("--json", o->json, "print as one JSON object"));
  CLI::Option* gen = c->add_option("--generate", o->generate, "write a synthetic milling force to this CSV instead (for examples)");
  generated.push_back(c->add_option("--duration", o->duration, "generated: length (default \"6 s\")"));
  generated.push_back(c->add_option("--rate", o->rate, "generated: sample rate (default \"500 Hz\")"));
  generated.push_back(c->add_option("--peak-force", o->peak_force, "generated: peak force of a tooth cutting one feed (\"500 N\")"));
  generated.push_back(c->add_option("--engagement", o->engagement, "generated: fraction of a revolution a tooth cuts (1/teeth)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            return (end != v.c_str() && *end == '\0' && x > 0.0 && x <= 1.0)
                       ? ""
                       : "'" + v + "' must be a fraction of a revolution above 0 and at most 1";
          },
          "(0, 1]")));
  generated.push_back(c->add_option("--runout", o->runout, "generated: radial run-out as a fraction of the feed per tooth (0.1)"));
  generated.push_back(c->add_option("--noise", o->noise, "generated: noise standard deviation (\"10 N\")"));
  generated.push_back(c->add_option("--seed", o->seed, "generated: noise seed (1)"));
  generated.push_back(c->add_option("--break-at", o->break_at, "generated: a tooth breaks at this time, e.g. \"3 s\""));
  generated.push_back(c->add_option("--broken-tooth", o->broken_tooth, "generated: which tooth breaks, 0 .. teeth - 1 (0)"));
  generated.push_back(c->add_option("--chatter-at", o->chatter_at, "generated: chatter starts at this time"));
  generated.push_back(c->add_option("--chatter-frequency", o->chatter_frequency, "generated: chatter frequency, e.g. \"173 Hz\""));
  generated.push_back(c->add_option("--chatter-force", o->chatter_force, "generated: chatter amplitude (\"300 N\")"));
  // an option of the other mode would be ignored: refused instead
  for (CLI::Option* r : reading) gen->excludes(r);
  for (CLI::Option* g : generated) g->needs(gen);
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
