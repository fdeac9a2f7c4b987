// polarcam export JOB|PATTERN --format thr|gcode|svg -o FILE [--tolerance "0.1 mm"] [--feed-mode inverse-time|axis]
//                 [--machine FILE] [--speed "40 mm/s"] [--json]
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "io/progress.hpp"
#include "cam/error.hpp"
#include "cam/units.hpp"
#include "io/output.hpp"
#include "pipeline/job_export.hpp"
#include "pipeline/job_tape.hpp"

namespace polarcam::cli {
namespace cmd_export {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string input, out, format, tolerance = "0.1 mm", feed_mode;
  PatternArgs pattern;
  bool json = false, quiet = false;
};

nlohmann::ordered_json summary_json(const Job& job, const ExportOptions& eo, const ExportResult& r,
                                    const std::string& out, uint64_t bytes) {
  nlohmann::ordered_json j;
  j["job"] = job.file;
  j["contour"] = job.contour->name();
  j["format"] = to_string(eo.format);
  j["output"] = out;
  j["bytes"] = bytes;
  j["tolerance_m"] = eo.tolerance;
  j["path_length_m"] = r.path_length_m;
  j["rho_max_m"] = r.rho_max_m;
  j["contours"] = job.contours;
  j["tool_lift"] = job_lifts_tool(job);
  if (eo.format == ExportFormat::svg) {
    j["points"] = r.points;
  } else {
    j["vertices"] = r.vertices;
  }
  if (r.gcode) {
    const GcodeStats& g = *r.gcode;
    j["feed_mode"] = job.machine.gcode && (eo.feed_mode ? *eo.feed_mode : job.machine.gcode->feed_mode) == FeedMode::axis
                         ? "axis"
                         : "inverse-time";
    j["speed_mps"] = job.motion.speed;
    if (job.motion.time_optimal) j["speed_profile"] = "time-optimal";
    j["lines"] = g.lines;
    j["g1"] = g.g1;
    j["limited"] = g.limited;
    j["centre_turns"] = g.centre_turns;
    if (job_lifts_tool(job)) {
      j["pen_ups"] = g.pen_ups;
      j["pen_downs"] = g.pen_downs;
      j["rapids"] = g.rapids;
    }
    j["duration_s"] = g.duration_s;
    j["max_speed_error_pct"] = g.max_speed_error_pct;
    j["ball_speed_min_mps"] = g.ball_speed_min_mps;
    j["ball_speed_max_mps"] = g.ball_speed_max_mps;
  }
  return j;
}

std::string summary_text(const Job& job, const ExportOptions& eo, const ExportResult& r, const std::string& out,
                         uint64_t bytes) {
  std::ostringstream os;
  os << "polarcam export " << job.file << "\n";
  os << "  contour    " << job.contour->name() << ", " << significant(r.path_length_m * 1e3, 6) << " mm long, up to "
     << significant(r.rho_max_m * 1e3, 6) << " mm from the pole\n";
  if (eo.format == ExportFormat::svg)
    os << "  drawing    " << thousands(r.points) << " points, chords within " << significant(eo.tolerance * 0.25e3, 4)
       << " mm\n";
  else
    os << "  theta-rho  " << thousands(r.vertices) << " vertices within " << significant(eo.tolerance * 1e3, 4) << " mm\n";
  if (r.gcode) {
    const GcodeStats& g = *r.gcode;
    os << "  G-code     " << thousands(g.lines) << " lines, " << thousands(g.g1) << " moves (" << thousands(g.limited)
       << " at an axis limit, " << thousands(g.centre_turns) << " turning at the centre), "
       << significant(g.duration_s, 6) << " s\n";
    os << "  ball speed " << significant(g.ball_speed_min_mps * 1e3, 4) << " .. "
       << significant(g.ball_speed_max_mps * 1e3, 4) << " mm/s ("
       << (job.motion.time_optimal ? "the time-optimal schedule, at most " : "asked ")
       << significant(job.motion.speed * 1e3, 4) << " mm/s; largest error " << significant(g.max_speed_error_pct, 3)
       << " % on moves not limited)\n";
  }
  os << "  " << to_string(eo.format) << std::string(9 - std::string(to_string(eo.format)).size(), ' ') << "  " << out
     << " (" << thousands(bytes) << " bytes)\n";
  return os.str();
}

int run(const Opts& o) {
  ExportOptions eo;
  if (o.format == "thr") eo.format = ExportFormat::thr;
  else if (o.format == "gcode") eo.format = ExportFormat::gcode;
  else if (o.format == "svg") eo.format = ExportFormat::svg;
  else throw InputError("must be thr, gcode or svg", "--format");
  eo.tolerance = option_quantity(o.tolerance, dim::length, "--tolerance");
  check_export_tolerance(eo.tolerance);
  if (!o.feed_mode.empty()) {
    if (eo.format != ExportFormat::gcode) throw InputError("applies to --format gcode only", "--feed-mode");
    if (o.feed_mode == "inverse-time") eo.feed_mode = FeedMode::inverse_time;
    else if (o.feed_mode == "axis") eo.feed_mode = FeedMode::axis;
    else throw InputError("must be inverse-time or axis", "--feed-mode");
  }
  check_output_path(o.out);
  // a .thr or SVG export is the path's geometry: only G-code carries the speed
  const Job job = load_job_input(o.input, o.pattern, eo.tolerance, eo.format == ExportFormat::gcode);
  OutputStream file(o.out);  // written as it is made, put in place when whole
  const ExportResult r = [&] {
    TerminalBar bar("export", o.quiet);  // erased before the output
    return export_job(job, eo, file.stream(), bar.callback());
  }();
  const uint64_t bytes = file.bytes();
  file.commit();
  if (o.json)
    std::cout << summary_json(job, eo, r, o.out, bytes).dump(2) << "\n";
  else
    std::cout << summary_text(job, eo, r, o.out, bytes);
  return 0;
}

}  // namespace cmd_export

void register_export(CLI::App& app, Action& action) {
  using namespace cmd_export;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("export", "Export the tool path as a theta-rho file, G-code or an SVG drawing");
  c->add_option("input", o->input, "job file (TOML) or pattern file")->required();
  c->add_option("--format", o->format, "thr (sand tables), gcode (the machine file's [gcode] table) or svg")->required();
  c->add_option("-o,--output", o->out, "the file to write")->required();
  c->add_option("--tolerance", o->tolerance, "largest distance of the theta-rho segments from the path (default 0.1 mm)");
  c->add_option("--feed-mode", o->feed_mode, "G-code: inverse-time (constant ball speed) or axis (constant axis feed)");
  add_pattern_options(c, o->pattern);
  c->add_flag("--json", o->json, "print the summary as one JSON object");
  c->add_flag("--quiet", o->quiet, "no progress bar (shown on a terminal only)");
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
