// polarcam compare JOB.toml [--json] [--report FILE.html] [--method dda|exact] [--rate HZ]
//                  [--speed-scale K] [--size-scale P/Q]
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "io/progress.hpp"
#include "pipeline/compare.hpp"
#include "report/compare_report.hpp"
#include "io/output.hpp"
#include "cam/error.hpp"
#include "cam/units.hpp"

namespace polarcam::cli {
namespace cmd_compare {  // named, not anonymous: the command files are compiled together (unity build)

std::string fmt(double v, int prec = 5) { return significant(v, prec); }

std::string summary_text(const Comparison& c) {
  const MachineSide& P = c.polar;
  const MachineSide& Q = c.cartesian;
  std::ostringstream os;
  os << "polarcam compare " << c.job_file << "\n";
  os << "  contour    " << c.contour << (c.closed ? " (closed)" : " (open)") << ", " << fmt(c.path_length_m * 1e3, 6)
     << " mm at " << fmt(c.nominal_speed * 1e3) << " mm/s\n";
  os << "  polar      " << P.grid << ", rule " << P.method << "\n";
  os << "  Cartesian  " << Q.grid << "\n\n";
  auto row = [&](const std::string& what, const std::string& a, const std::string& b) {
    os << "  " << std::left << std::setw(34) << what << std::setw(26) << a << b << "\n";
  };
  row("", "polar", std::string("Cartesian (") + Q.method + ")");
  row("steps " + P.axis[0] + " / " + Q.axis[0], thousands(P.steps[0]), thousands(Q.steps[0]));
  row("steps " + P.axis[1] + " / " + Q.axis[1], thousands(P.steps[1]), thousands(Q.steps[1]));
  row("steps total", thousands(P.steps_total()), thousands(Q.steps_total()));
  row("contouring time, s", fmt(P.duration_s, 7), fmt(Q.duration_s, 7));
  row("speed min .. max, mm/s", fmt(P.speed.min_mps * 1e3) + " .. " + fmt(P.speed.max_mps * 1e3),
      fmt(Q.speed.min_mps * 1e3) + " .. " + fmt(Q.speed.max_mps * 1e3));
  row("speed RMS deviation, mm/s", fmt(P.speed.rms_dev_mps * 1e3, 4), fmt(Q.speed.rms_dev_mps * 1e3, 4));
  row("area error, mm^2", fmt(P.area_m2 * 1e6), fmt(Q.area_m2 * 1e6));
  row("deviation, mm", fmt(P.deviation_m * 1e3), fmt(Q.deviation_m * 1e3));
  row("max step rate " + P.axis[0] + " / " + Q.axis[0] + ", Hz", fmt(P.rates[0].max_rate_hz), fmt(Q.rates[0].max_rate_hz));
  row("max step rate " + P.axis[1] + " / " + Q.axis[1] + ", Hz", fmt(P.rates[1].max_rate_hz), fmt(Q.rates[1].max_rate_hz));
  row("tape, bytes", thousands(P.tape_bytes), thousands(Q.tape_bytes));
  row("resolution at the worst point, mm", fmt(P.resolution_worst_m * 1e3, 4), fmt(Q.resolution_worst_m * 1e3, 4));
  os << "\n  which machine wins, for this job:\n";
  for (const AttributeVerdict& v : c.verdicts) {
    const std::string w = v.winner == "tie" ? "tie" : (v.winner == "polar" ? "polar" : "Cartesian");
    os << "    " << std::left << std::setw(52) << v.attribute << w << "\n      " << v.why << "\n";
  }
  return os.str();
}

}  // namespace cmd_compare

void register_compare(CLI::App& app, Action& action) {
  using namespace cmd_compare;
  struct Opts {
    std::string job, report, method = "dda", rate, speed_scale = "2", size_scale = "1/2";
    PatternArgs pattern;
    bool json = false, quiet = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "compare", "The job on the polar machine and on a Cartesian machine of the same resolution and speed, side by side");
  c->add_option("job", o->job, "job file (TOML)")->required();
  add_pattern_options(c, o->pattern);
  c->add_flag("--json", o->json, "print the comparison as one JSON object");
  c->add_flag("--quiet", o->quiet, "no progress bar (shown on a terminal only)");
  c->add_option("--report", o->report, "write a self-contained HTML report with figures");
  c->add_option("--method", o->method, "the Cartesian machine: dda (lines and arcs, DDAs; default) or exact")
      ->check(CLI::IsMember({"dda", "exact"}));
  c->add_option("--rate", o->rate, "interrupt rate of the DDA control, e.g. 5000 or \"5 kHz\" (default: the job's)");
  c->add_option("--speed-scale", o->speed_scale, "K of the speed-scaling test (default 2)");
  c->add_option("--size-scale", o->size_scale, "P/Q of the size-scaling test (default 1/2)");
  c->callback([o, &action] {
    action = [o] {
      if (!o->report.empty()) {  // before any work
        check_output_path(o->report);
        check_output_extension(o->report, {".html", ".htm"}, "the report");
      }
      CompareOptions opt;
      opt.method = o->method == "exact" ? CartesianMethod::exact : CartesianMethod::dda;
      if (!o->rate.empty()) {
        if (opt.method == CartesianMethod::exact) throw InputError("--rate applies to --method dda only");
        opt.rate = parse_rate_option(o->rate);
      }
      opt.speed_scale = parse_ratio(o->speed_scale, "--speed-scale");
      opt.size_scale = parse_ratio(o->size_scale, "--size-scale");
      opt.figures = !o->report.empty();
      const Job job = load_job_input(o->job, o->pattern);
      const Comparison cmp = [&] {
        TerminalBar bar("compare", o->quiet);  // erased before the output
        return compare_job(job, opt, bar.callback());
      }();
      if (!o->report.empty()) write_compare_report(cmp, o->report);
      if (o->json)
        std::cout << to_json(cmp).dump(2) << "\n";
      else
        std::cout << summary_text(cmp);
      return 0;
    };
  });
}

}  // namespace polarcam::cli
