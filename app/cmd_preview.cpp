// polarcam preview JOB|PATTERN|TAPE -o FILE.png|.svg [--machine M --speed V] [--resolution "0.1 mm"] [--json]
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "digitizer/tape_file.hpp"
#include "cam/error.hpp"
#include "cam/units.hpp"
#include "pipeline/preview.hpp"
#include "report/plot.hpp"
#include "report/preview_figure.hpp"

namespace polarcam::cli {

void register_preview(CLI::App& app, Action& action) {
  struct Opts {
    std::string input, out, resolution = "0.1 mm";
    PatternArgs pattern;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("preview", "Draw what the machine will draw: the tool path, the stepped motion, "
                                              "start and end, and where it is slower than asked, on the work area");
  c->add_option("input", o->input, "job file (TOML), pattern (.thr, .svg, .dxf, .csv) or step tape (.tape)")->required();
  c->add_option("-o,--output", o->out, "the picture: .png or .svg")->required();
  add_pattern_options(c, o->pattern);
  c->add_option("--resolution", o->resolution, "draw the stepped motion at points this far apart (default 0.1 mm)");
  c->add_flag("--json", o->json, "print what was drawn as one JSON object");
  c->callback([o, &action] {
    action = [o] {
      const double res = option_quantity(o->resolution, dim::length, "--resolution");
      if (!(res > 0.0)) throw InputError("must be a positive length", "--resolution");
      const std::string ext = std::filesystem::path(o->out).extension().string();
      if (ext != ".png" && ext != ".svg") throw InputError("the picture is written as .png or .svg", "-o");
      plot::check_plot_path(o->out);
      const bool tape = is_tape_file(o->input);
      check_trace_options_apply(o->pattern, o->input);
      if (tape && (!o->pattern.machine.empty() || !o->pattern.speed.empty()))
        throw InputError("a tape carries its machine and speed: --machine and --speed apply to patterns", "--machine");
      Preview pv;
      if (tape) {
        pv = preview_tape(o->input, res * 1e3);
      } else {
        // the job's steps, as digitize makes them: a motor driven above its step rate is warned of as digitize does
        const Job job = load_job_input(o->input, o->pattern);
        DigitizedJob d;
        pv = preview_job(job, res * 1e3, &d);
        warn_step_rate_excess(job, d.result);
      }
      save_preview(pv, o->out);
      if (o->json) {
        nlohmann::ordered_json j;
        j["input"] = o->input;
        j["output"] = o->out;
        j["steps"] = pv.steps;
        size_t stepped = 0, rapid = 0, path = 0;
        for (const Polyline& l : pv.stepped) stepped += l.x.size();
        for (const Polyline& l : pv.rapids) rapid += l.x.size();
        for (const Polyline& l : pv.path) path += l.x.size();
        j["stepped_points"] = stepped;
        j["path_points"] = path;
        j["contours"] = pv.path.size();
        j["rapid_moves"] = pv.rapids.size();
        j["rapid_points"] = rapid;
        j["slowed_stretches"] = pv.slowed.size();
        j["start_mm"] = {pv.start[0], pv.start[1]};
        j["end_mm"] = {pv.end[0], pv.end[1]};
        std::cout << j.dump(2) << "\n";
      }
      return 0;
    };
  });
}

}  // namespace polarcam::cli
