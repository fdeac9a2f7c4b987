// polarcam check PATTERN.thr [--machine M --speed V] [--json] [--fix -o CLEAN.thr]
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "cam/input_file.hpp"
#include "cam/thr_file.hpp"
#include "io/output.hpp"
#include "io/progress.hpp"
#include "pipeline/job_tape.hpp"

namespace polarcam::cli {
namespace cmd_check {  // named, not anonymous: the command files are compiled together (unity build)

std::string fmt(double v, int prec = 6) { return significant(v, prec); }

const char* end_place(double rho) { return rho == 0.0 ? "centre" : rho == 1.0 ? "rim" : "neither centre nor rim"; }

}  // namespace cmd_check

void register_check(CLI::App& app, Action& action) {
  using namespace cmd_check;
  struct Opts {
    std::string pattern, out;
    PatternArgs machine;
    bool json = false, fix = false, quiet = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("check", "Check a theta-rho pattern: counts, radius range, repeated points, centre "
                                            "crossings, where it starts and ends, length and drawing time");
  c->add_option("pattern", o->pattern, "theta-rho pattern (.thr)")->required();
  add_pattern_options(c, o->machine);
  c->add_flag("--json", o->json, "print the findings as one JSON object");
  c->add_flag("--quiet", o->quiet, "no progress bar while the pattern is stepped on the machine (a terminal only)");
  c->add_flag("--fix", o->fix, "write the pattern normalised (repeated points merged, comments dropped) to -o");
  c->add_option("-o,--output", o->out, "the normalised pattern (with --fix)");
  c->callback([o, &action] {
    action = [o] {
      if (o->fix != !o->out.empty()) throw InputError("--fix and -o go together: --fix -o CLEAN.thr", "--fix");
      if (o->fix) check_output_path(o->out);
      if (lower_extension(o->pattern) != ".thr")
        throw InputError("check reads theta-rho patterns (.thr); a drawing or an image is checked by drawing it: "
                         "polarcam preview FILE --machine M --speed V",
                         o->pattern);
      check_trace_options_apply(o->machine, o->pattern);
      const ThrPattern p = read_thr(o->pattern);
      const ThrStats st = thr_stats(p.vertices);
      nlohmann::ordered_json j;
      j["pattern"] = o->pattern;
      j["lines"] = p.lines;
      j["points"] = p.points;
      j["repeated_points"] = p.merged;
      j["vertices"] = st.vertices;
      j["theta_min_rad"] = st.theta_min;
      j["theta_max_rad"] = st.theta_max;
      j["turns"] = (st.theta_max - st.theta_min) / (2 * M_PI);
      j["rho_min"] = st.rho_min;
      j["rho_max"] = st.rho_max;
      j["centre_touches"] = st.centre_touches;
      j["start_rho"] = st.start_rho;
      j["end_rho"] = st.end_rho;
      j["starts_at"] = end_place(st.start_rho);
      j["ends_at"] = end_place(st.end_rho);
      j["length_radii"] = st.length;
      if (!o->machine.machine.empty() || !o->machine.speed.empty()) {
        // on a machine: the exact length, time and steps of the tape the pattern makes
        const Job job = load_job_input(o->pattern, o->machine);
        const DigitizedJob d = [&] {
          TerminalBar bar("check", o->quiet);  // erased before the output
          return digitize_job(job, nullptr, bar.callback());
        }();
        j["path_length_m"] = d.result.path_length_m;
        j["duration_s"] = d.result.duration_s;
        j["steps_radial"] = d.result.radial.steps();
        j["steps_angular"] = d.result.angular.steps();
        j["max_step_rate_radial_hz"] = d.result.radial.max_rate_hz;
        j["max_step_rate_angular_hz"] = d.result.angular.max_rate_hz;
      }
      if (o->fix) {
        std::ostringstream os;
        write_thr(os, p.vertices, {"normalised by polarcam check from " + std::filesystem::path(o->pattern).filename().string(),
                                   std::to_string(p.merged) + (p.merged == 1 ? " repeated point merged" : " repeated points merged")});
        write_file_atomic(o->out, os.str());
        j["fixed"] = o->out;
      }
      if (o->json) {
        std::cout << j.dump(2) << "\n";
        return 0;
      }
      std::cout << "polarcam check " << o->pattern << "\n"
                << "  points     " << thousands(p.points) << " (" << thousands(p.merged) << " repeated, merged), "
                << thousands(st.vertices) << " vertices\n"
                << "  theta      " << fmt(st.theta_min) << " .. " << fmt(st.theta_max) << " rad ("
                << fmt(j["turns"].get<double>(), 4) << " turns)\n"
                << "  rho        " << fmt(st.rho_min) << " .. " << fmt(st.rho_max) << ", " << st.centre_touches
                << " passes through the centre\n"
                << "  starts     at rho " << fmt(st.start_rho) << " (" << end_place(st.start_rho) << "), ends at rho "
                << fmt(st.end_rho) << " (" << end_place(st.end_rho) << ")\n"
                << "  length     " << fmt(st.length) << " table radii\n";
      if (j.contains("duration_s"))
        std::cout << "  on machine " << fmt(j["path_length_m"].get<double>() * 1e3) << " mm, "
                  << fmt(j["duration_s"].get<double>()) << " s, " << thousands(j["steps_radial"].get<uint64_t>())
                  << " radial and " << thousands(j["steps_angular"].get<uint64_t>()) << " angular steps\n";
      if (o->fix) std::cout << "  written    " << o->out << "\n";
      return 0;
    };
  });
}

}  // namespace polarcam::cli
