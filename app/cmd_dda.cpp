// polarcam dda JOB.toml [-o OUT.tape] [--method dda|exact] [--rate HZ] [--json]
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "app/cli.hpp"
#include "pipeline/job_cartesian.hpp"
#include "io/output.hpp"
#include "cam/error.hpp"
#include "cam/units.hpp"

namespace polarcam::cli {
namespace cmd_dda {  // named, not anonymous: the command files are compiled together (unity build)

nlohmann::ordered_json summary_json(const Job& job, const CartesianRun& run, const std::string& out) {
  const CartesianResult& r = run.result;
  nlohmann::ordered_json j;
  j["job"] = job.file;
  j["contour"] = job.contour->name();
  j["closed"] = r.closed;
  j["method"] = to_string(run.method);
  j["resolution_m"] = run.blu;
  j["steps_x"] = r.axis[0].steps();
  j["steps_y"] = r.axis[1].steps();
  j["steps_total"] = r.steps();
  j["steps_x_plus"] = r.axis[0].plus;
  j["steps_x_minus"] = r.axis[0].minus;
  j["steps_y_plus"] = r.axis[1].plus;
  j["steps_y_minus"] = r.axis[1].minus;
  j["duration_s"] = r.duration_s;
  j["last_step_s"] = static_cast<double>(r.last_step_ns) * 1e-9;
  j["path_length_m"] = r.path_length_m;
  j["speed_nominal_mps"] = run.nominal_speed;
  j["speed_avg_mps"] = r.duration_s > 0 ? r.path_length_m / r.duration_s : 0.0;
  j["speed_min_mps"] = run.speed.min_mps;
  j["speed_max_mps"] = run.speed.max_mps;
  j["speed_mean_mps"] = run.speed.mean_mps;
  j["speed_rms_dev_mps"] = run.speed.rms_dev_mps;
  j["speed_samples"] = run.speed.samples;
  j["max_step_rate_x_hz"] = r.axis[0].max_rate_hz;
  j["max_step_rate_y_hz"] = r.axis[1].max_rate_hz;
  j["min_step_interval_x_ns"] = r.axis[0].min_interval_ns;
  j["min_step_interval_y_ns"] = r.axis[1].min_interval_ns;
  j["start_node"] = {r.start[0], r.start[1]};
  j["end_node"] = {r.end[0], r.end[1]};
  j["returns_to_start"] = r.returns_to_start;
  if (run.method == CartesianMethod::dda) {
    j["interrupt_rate_hz"] = run.interrupt_rate;
    j["tolerance_m"] = job.cartesian.tolerance;
    j["fit_lines"] = run.fit.lines;
    j["fit_arcs"] = run.fit.arcs;
    j["fit_deviation_max_m"] = run.fit.max_deviation;
    j["blocks"] = run.program.blocks.size();
    j["blocks_line"] = run.program.line_blocks;
    j["blocks_arc"] = run.program.arc_blocks;
    j["dda_cycles"] = run.dda.cycles;
    j["interrupts"] = run.dda.interrupts;
    j["cleanup_steps"] = run.dda.cleanup_steps;
  }
  if (!out.empty()) j["tape"] = out;
  return j;
}

std::string fmt(double v, int prec = 6) { return significant(v, prec); }

std::string summary_text(const Job& job, const CartesianRun& run, const std::string& out) {
  const CartesianResult& r = run.result;
  std::ostringstream os;
  os << "polarcam dda " << job.file << " (method " << to_string(run.method);
  if (run.method == CartesianMethod::dda) os << ", " << fmt(run.interrupt_rate) << " Hz interrupts";
  os << ")\n";
  os << "  contour    " << job.contour->name() << (r.closed ? " (closed)" : " (open)") << ", tool radius "
     << fmt(job.tool.radius * 1e3) << " mm\n";
  os << "  grid       BLU = " << fmt(run.blu * 1e3) << " mm on x and y, origin at the contour pole\n";
  if (run.method == CartesianMethod::dda) {
    os << "  program    " << run.fit.lines << " lines and " << run.fit.arcs << " arcs within "
       << fmt(job.cartesian.tolerance * 1e3) << " mm (largest deviation " << fmt(run.fit.max_deviation * 1e3, 3)
       << " mm) -> " << run.program.blocks.size() << " blocks, " << thousands(run.dda.cycles) << " DDA cycles\n";
  }
  os << "  steps      x " << thousands(r.axis[0].steps()) << " (+" << thousands(r.axis[0].plus) << " / -"
     << thousands(r.axis[0].minus) << "), y " << thousands(r.axis[1].steps()) << " (+" << thousands(r.axis[1].plus)
     << " / -" << thousands(r.axis[1].minus) << "), total " << thousands(r.steps()) << "\n";
  os << "  time       " << fmt(r.duration_s) << " s for " << fmt(r.path_length_m * 1e3) << " mm (average "
     << fmt(r.duration_s > 0 ? r.path_length_m / r.duration_s * 1e3 : 0.0, 5) << " mm/s)\n";
  os << "  speed      from the pulse rates: " << fmt(run.speed.min_mps * 1e3, 5) << " .. "
     << fmt(run.speed.max_mps * 1e3, 5) << " mm/s, RMS deviation " << fmt(run.speed.rms_dev_mps * 1e3, 4)
     << " mm/s from " << fmt(run.nominal_speed * 1e3, 5) << " mm/s\n";
  os << "  rates      max step rate x " << fmt(r.axis[0].max_rate_hz, 5) << " Hz, y " << fmt(r.axis[1].max_rate_hz, 5)
     << " Hz\n";
  os << "  nodes      start [" << r.start[0] << ", " << r.start[1] << "], end [" << r.end[0] << ", " << r.end[1] << "]";
  if (r.closed) os << (r.returns_to_start ? " (returns to its start)" : " (does NOT return to its start node)");
  os << "\n";
  if (!out.empty()) {
    os << "  tape       " << out;
    if (const auto size = regular_file_size(out)) os << " (" << thousands(*size) << " bytes)";
    os << "\n";
  }
  return os.str();
}

}  // namespace cmd_dda

void register_dda(CLI::App& app, Action& action) {
  using namespace cmd_dda;
  struct Opts {
    std::string job, out, method = "dda", rate;
    PatternArgs pattern;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "dda", "Step a job on a Cartesian machine: DDA interpolation of lines and arcs, or exact step times");
  c->add_option("job", o->job, "job file (TOML)")->required();
  add_pattern_options(c, o->pattern);
  c->add_option("-o,--output", o->out, "write the step tape (axes x and y) to this file");
  c->add_option("--method", o->method, "dda (linear and circular DDAs, feed accumulator) or exact")
      ->check(CLI::IsMember({"dda", "exact"}));
  c->add_option("--rate", o->rate, "interrupt rate of the DDA control, e.g. 5000 or \"5 kHz\" (default: the job's)");
  c->add_flag("--json", o->json, "print the summary as one JSON object");
  c->callback([o, &action] {
    action = [o] {
      const CartesianMethod m = o->method == "exact" ? CartesianMethod::exact : CartesianMethod::dda;
      std::optional<double> rate;
      if (!o->rate.empty()) {
        if (m == CartesianMethod::exact) throw InputError("--rate applies to --method dda only");
        rate = parse_rate_option(o->rate);
      }
      Job job = load_job_input(o->job, o->pattern);
      const double hz = cartesian_interrupt_rate(job, rate);
      CartesianRun run = run_cartesian_job_to_tape(job, m, hz, o->out);
      if (o->json)
        std::cout << summary_json(job, run, o->out).dump(2) << "\n";
      else
        std::cout << summary_text(job, run, o->out);
      return 0;
    };
  });
}

}  // namespace polarcam::cli
