// polarcam error TAPE --job JOB.toml [--json] [--segments N] [--threads N]: polar or Cartesian tapes
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "io/output.hpp"
#include "io/progress.hpp"
#include "job/job.hpp"
#include "pipeline/tape_metrics.hpp"
#include "cam/error.hpp"
#include "digitizer/tape.hpp"
#include "metrics/error_metrics.hpp"
#include "optimize/placement.hpp"

namespace polarcam::cli {
namespace cmd_error {  // named, not anonymous: the command files are compiled together (unity build)

std::string fmt(double v, int prec = 6) { return significant(v, prec); }

struct Opts {
  std::string tape, job;
  PatternArgs pattern;
  bool json = false, quiet = false;
  int segments = 0;
  int threads = 0;
};

// A Cartesian tape: area error and deviation (F1 is a polar measure).
int cartesian(const Opts& o, const Job& job) {
  if (o.segments > 0) throw InputError("--segments: F_sum, F_dif and F1 apply to polar tapes only");
  const CartesianTapeMetrics cm = [&] {
    TerminalBar bar("error", o.quiet);  // erased before the output
    return cartesian_tape_metrics(job, o.tape, bar.callback());
  }();
  const CartesianErrorMetrics& m = cm.m;
  if (o.json) {
    nlohmann::ordered_json j;
    j["tape"] = o.tape;
    j["job"] = job.file;
    j["axes"] = "cartesian";
    j["rule"] = to_string(cm.rule);
    j["area_error_mm2"] = m.area.area_m2 * 1e6;
    j["deviation_max_mm"] = m.deviation_max_m * 1e3;
    j["deviation_at_mm"] = {m.deviation_at.x * 1e3, m.deviation_at.y * 1e3};
    j["steps_x"] = m.area.run_steps;
    j["steps_y"] = m.area.rise_steps;
    j["strips"] = m.area.sectors;
    j["general_strips"] = m.area.general_sectors;
    j["resolution_m"] = cm.blu;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::ostringstream os;
  os << "polarcam error " << o.tape << " (Cartesian, " << to_string(cm.rule) << ") against " << job.file << "\n";
  os << "  area error   " << fmt(m.area.area_m2 * 1e6) << " mm^2 (" << m.area.sectors << " strips of x, "
     << m.area.general_sectors << " by the general sweep)\n";
  os << "  deviation    " << fmt(m.deviation_max_m * 1e3) << " mm at x = " << fmt(m.deviation_at.x * 1e3)
     << " mm, y = " << fmt(m.deviation_at.y * 1e3) << " mm (contour frame); BLU " << fmt(cm.blu * 1e3) << " mm\n";
  std::cout << os.str();
  return 0;
}

}  // namespace cmd_error

void register_error(CLI::App& app, Action& action) {
  using namespace cmd_error;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("error", "Contouring error of a step tape against its job's tool path: exact area "
                                            "error, deviation, and for polar tapes the thesis's F_sum, F_dif and F1");
  c->add_option("tape", o->tape, "step tape (polar, any rule; or Cartesian)")->required();
  c->add_option("--job", o->job, "the job the tape was made from (its tool path is the reference)")->required();
  add_pattern_options(c, o->pattern);
  c->add_flag("--json", o->json, "print the metrics as one JSON object");
  c->add_flag("--quiet", o->quiet, "no progress bar (shown on a terminal only)");
  c->add_option("--segments", o->segments, "segments for F_sum, F_dif, F1 (default: the job's [optimize] segments, 100)")
      ->check(CLI::Range(1, 100000));
  c->add_option("--threads", o->threads,
                "threads (default: all cores; 2 or more measure the area error beside the deviation; the result does "
                "not depend on it)")
      ->check(CLI::Range(1, 1024));
  c->callback([o, &action] {
    action = [o] {
      const Job job = load_job_input(o->job, o->pattern, 1e-4, false);  // the metrics are geometry alone
      TapeAxes axes;
      {
        TapeReader rd(o->tape);
        axes = rd.header().axes;
      }
      if (axes == TapeAxes::cartesian) return cartesian(*o, job);
      const PolarTapeMetrics pm = [&] {
        TerminalBar bar("error", o->quiet);  // erased before the output
        const int threads = o->threads > 0 ? o->threads : default_threads();
        return polar_tape_metrics(job, o->tape, o->segments, bar.callback(), threads);
      }();
      const ErrorMetrics& m = pm.m;
      const Grid& g = pm.grid;
      if (o->json) {
        nlohmann::ordered_json j;
        j["tape"] = o->tape;
        j["job"] = job.file;
        j["axes"] = "polar";
        j["rule"] = to_string(pm.rule);
        j["area_error_mm2"] = m.area.area_m2 * 1e6;
        j["deviation_max_mm"] = m.deviation_max_m * 1e3;
        j["deviation_at_mm"] = {m.deviation_at.x * 1e3, m.deviation_at.y * 1e3};
        j["deviation_eq41_mm"] = m.deviation_eq41_m * 1e3;
        j["F_sum"] = m.f_counts.F_sum;
        j["F_dif"] = m.f_counts.F_dif;
        j["F1"] = m.f_counts.F1;
        j["F_sum_chords"] = m.f_chords.F_sum;
        j["F_dif_chords"] = m.f_chords.F_dif;
        j["F1_chords"] = m.f_chords.F1;
        j["segments"] = m.segments;
        j["steps_radial"] = m.area.rise_steps;
        j["steps_angular"] = m.area.run_steps;
        j["sectors"] = m.area.sectors;
        j["general_sectors"] = m.area.general_sectors;
        j["radial_resolution_m"] = g.dr;
        j["angular_resolution_rad"] = g.dtheta;
        std::cout << j.dump(2) << "\n";
        return 0;
      }
      std::ostringstream os;
      os << "polarcam error " << o->tape << " (rule " << to_string(pm.rule) << ") against " << job.file << "\n";
      os << "  area error   " << fmt(m.area.area_m2 * 1e6) << " mm^2 (" << m.area.sectors << " sectors, "
         << m.area.general_sectors << " by the general sweep)\n";
      os << "  deviation    " << fmt(m.deviation_max_m * 1e3) << " mm at x = " << fmt(m.deviation_at.x * 1e3)
         << " mm, y = " << fmt(m.deviation_at.y * 1e3) << " mm; Eq. 4.1 bound " << fmt(m.deviation_eq41_m * 1e3)
         << " mm\n";
      os << "  F1 (steps)   " << fmt(m.f_counts.F1) << " = F_dif " << fmt(m.f_counts.F_dif) << " / F_sum "
         << fmt(m.f_counts.F_sum) << " over " << m.segments << " segments\n";
      os << "  F1 (chords)  " << fmt(m.f_chords.F1) << " = " << fmt(m.f_chords.F_dif) << " / " << fmt(m.f_chords.F_sum)
         << " (Eq. 4.15)\n";
      std::cout << os.str();
      return 0;
    };
  });
}

}  // namespace polarcam::cli
