// polarcam digitize JOB.toml [-o OUT.tape] [--json]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "digitizer/template_speed.hpp"
#include "io/progress.hpp"
#include "pipeline/job_tape.hpp"
#include "io/output.hpp"

namespace polarcam::cli {
namespace cmd_digitize {  // named, not anonymous: the command files are compiled together (unity build)

const char* side_name(ToolSide s) {
  static const char* names[] = {"left", "right", "outside", "inside"};
  return names[static_cast<int>(s)];
}

nlohmann::ordered_json template_point_json(const TemplatePoint& q) {
  nlohmann::ordered_json j;
  j["s_m"] = q.s;
  j["x_m"] = q.p.x;
  j["y_m"] = q.p.y;
  j["radius_of_curvature_m"] = std::isinf(q.radius_m) ? nlohmann::ordered_json() : nlohmann::ordered_json(q.radius_m);
  j["centre_of_curvature"] = q.c == 0.0 ? "none" : q.side == CurvatureSide::roller ? "roller_side" : "other_side";
  j["v_star"] = q.v_star;
  j["speed_mps"] = q.speed_mps;
  return j;
}

// The template digitizer's speed along the path ([motion] speed_profile = "template"): its range and the point
// where it departs most from V_t (x, y in the machine frame).
nlohmann::ordered_json template_json(const Job& job, const TemplateSpeed& t) {
  const TemplateSpeedRange& r = t.range();
  nlohmann::ordered_json j;
  j["set_speed_mps"] = t.set_speed();
  j["thickness_m"] = job.motion.rollers->thickness;
  j["roller_radius_m"] = job.motion.rollers->roller_radius;
  j["side"] = side_name(job.motion.rollers->side);
  j["speed_min_mps"] = r.slowest.speed_mps;
  j["speed_max_mps"] = r.fastest.speed_mps;
  j["v_star_min"] = r.slowest.v_star;
  j["v_star_max"] = r.fastest.v_star;
  j["worst"] = template_point_json(r.worst);
  return j;
}

nlohmann::ordered_json summary_json(const Job& job, const DigitizedJob& d, const std::string& out) {
  const DigitizeResult& r = d.result;
  nlohmann::ordered_json j;
  j["job"] = job.file;
  j["contour"] = job.contour->name();
  j["contours"] = job.contours;  // contours in the job, joined in order (drawn, or by rapid moves with the tool up)
  j["tool_lift"] = d.lifted.has_value();
  if (d.lifted) {
    j["tool_events"] = 2 * d.lifted->paths.size() - 2;
    j["drawn_length_m"] = d.lifted->drawn_length_m;
    j["rapid_moves"] = d.lifted->rapids.size();
    j["rapid_length_m"] = d.lifted->rapid_length_m;
    j["rapid_time_s"] = d.lifted->rapid_time_s;
    j["rapid_steps"] = d.lifted->rapid_steps;
    j["rapid_speed_mps"] = job_rapid_speed(job);
  }
  j["closed"] = r.closed;
  j["rule"] = to_string(job.motion.rule);
  j["steps_radial"] = r.radial.steps();
  j["steps_angular"] = r.angular.steps();
  j["steps_total"] = r.radial.steps() + r.angular.steps();
  j["steps_radial_plus"] = r.radial.plus;
  j["steps_radial_minus"] = r.radial.minus;
  j["steps_angular_plus"] = r.angular.plus;
  j["steps_angular_minus"] = r.angular.minus;
  j["duration_s"] = r.duration_s;
  j["last_step_s"] = static_cast<double>(r.last_step_ns) * 1e-9;
  j["path_length_m"] = r.path_length_m;
  j["max_step_rate_radial_hz"] = r.radial.max_rate_hz;
  j["max_step_rate_angular_hz"] = r.angular.max_rate_hz;
  j["min_step_interval_radial_ns"] = r.radial.min_interval_ns;
  j["min_step_interval_angular_ns"] = r.angular.min_interval_ns;
  j["start_node"] = {r.start_n, r.start_m};
  j["end_node"] = {r.end_n, r.end_m};
  j["returns_to_start"] = r.returns_to_start;
  j["winding"] = r.winding;
  j["radial_resolution_m"] = job.machine.grid.dr;
  j["angular_resolution_rad"] = job.machine.grid.dtheta;
  j["angular_steps_per_rev"] = job.machine.grid.steps_per_rev;
  const PathRanges pr = path_ranges(d);
  j["r_min_path_m"] = pr.r_min;
  j["r_max_path_m"] = pr.r_max;
  j["theta_min_path_rad"] = pr.theta_min;
  j["theta_max_path_rad"] = pr.theta_max;
  if (const auto* t = dynamic_cast<const TemplateSpeed*>(d.profile.get())) j["template_speed"] = template_json(job, *t);
  if (!out.empty()) j["tape"] = out;
  return j;
}

std::string fmt(double v, int prec = 6) { return significant(v, prec); }

std::string summary_text(const Job& job, const DigitizedJob& d, const std::string& out) {
  const DigitizeResult& r = d.result;
  std::ostringstream os;
  os << "polarcam digitize " << job.file << "\n";
  os << "  contour    " << job.contour->name() << (r.closed ? " (closed)" : " (open)") << ", tool radius "
     << fmt(job.tool.radius * 1e3) << " mm\n";
  os << "  placement  C = " << fmt(job.placement.C * 1e3) << " mm, beta = " << fmt(job.placement.beta) << " rad\n";
  os << "  grid       dR = " << fmt(job.machine.grid.dr * 1e3) << " mm, dtheta = " << fmt(job.machine.grid.dtheta) << " rad";
  if (job.machine.grid.steps_per_rev) os << " (" << job.machine.grid.steps_per_rev << " steps/rev)";
  os << ", rule " << to_string(job.motion.rule) << "\n";
  const PathRanges pr = path_ranges(d);
  os << "  path       " << fmt(r.path_length_m * 1e3) << " mm long, r " << fmt(pr.r_min * 1e3) << " .. "
     << fmt(pr.r_max * 1e3) << " mm, theta " << fmt(pr.theta_min) << " .. " << fmt(pr.theta_max) << " rad\n";
  if (d.lifted)
    os << "  contours   " << d.lifted->paths.size() << ", " << fmt(d.lifted->drawn_length_m * 1e3)
       << " mm drawn; tool lifted between them: " << d.lifted->rapids.size() << " rapid moves, "
       << fmt(d.lifted->rapid_length_m * 1e3) << " mm in " << fmt(d.lifted->rapid_time_s) << " s at "
       << fmt(job_rapid_speed(job) * 1e3) << " mm/s\n";
  os << "  steps      radial " << thousands(r.radial.steps()) << " (+" << thousands(r.radial.plus) << " / -"
     << thousands(r.radial.minus) << "), angular " << thousands(r.angular.steps()) << " (+" << thousands(r.angular.plus)
     << " / -" << thousands(r.angular.minus) << "), total " << thousands(r.radial.steps() + r.angular.steps()) << "\n";
  os << "  time       " << fmt(r.duration_s) << " s; max step rate radial " << fmt(r.radial.max_rate_hz, 5)
     << " Hz, angular " << fmt(r.angular.max_rate_hz, 5) << " Hz\n";
  if (const auto* t = dynamic_cast<const TemplateSpeed*>(d.profile.get())) {
    const TemplateSpeedRange& tr = t->range();
    os << "  template   speed " << fmt(tr.slowest.speed_mps * 1e3) << " .. " << fmt(tr.fastest.speed_mps * 1e3)
       << " mm/s (V_t " << fmt(t->set_speed() * 1e3) << " mm/s); furthest from V_t: " << fmt(100.0 * (tr.worst.v_star - 1.0), 4)
       << " % at (" << fmt(tr.worst.p.x * 1e3) << ", " << fmt(tr.worst.p.y * 1e3) << ") mm";
    if (!std::isinf(tr.worst.radius_m))
      os << ", radius of curvature " << fmt(tr.worst.radius_m * 1e3) << " mm on the "
         << (tr.worst.side == CurvatureSide::roller ? "driven roller's side" : "other side");
    os << "\n";
  }
  os << "  nodes      start [" << r.start_n << ", " << r.start_m << "], end [" << r.end_n << ", " << r.end_m << "]";
  if (r.closed) os << (r.returns_to_start ? " (returns to its start)" : " (does NOT return to its start node)");
  os << "\n";
  if (!out.empty()) {
    os << "  tape       " << out;
    if (const auto size = regular_file_size(out)) os << " (" << thousands(*size) << " bytes)";
    os << "\n";
  }
  return os.str();
}

}  // namespace cmd_digitize

void register_digitize(CLI::App& app, Action& action) {
  using namespace cmd_digitize;
  struct Opts {
    std::string job, out;
    PatternArgs pattern;
    bool json = false, quiet = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("digitize", "Digitize a job into a step tape and print its summary");
  c->add_option("job", o->job, "job file (TOML)")->required();
  add_pattern_options(c, o->pattern);
  c->add_option("-o,--output", o->out, "write the step tape to this file");
  c->add_flag("--json", o->json, "print the summary as one JSON object");
  c->add_flag("--quiet", o->quiet, "no progress bar (shown on a terminal only)");
  c->callback([o, &action] {
    action = [o] {
      Job job = load_job_input(o->job, o->pattern);
      DigitizedJob d;
      {
        TerminalBar bar("digitize", o->quiet);  // erased before the output
        if (!o->out.empty()) {
          TapeHeader h = tape_header_for(job);
          TapeWriter w(o->out, h);
          d = digitize_job(job, &w, bar.callback());
          complete_header(h, d.result);
          w.finish(h);
        } else {
          d = digitize_job(job, nullptr, bar.callback());
        }
      }
      // the tape is still written (a faster controller or a slower replay may run it): a warning, not an error
      warn_step_rate_excess(job, d.result);
      if (o->json)
        std::cout << summary_json(job, d, o->out).dump(2) << "\n";
      else
        std::cout << summary_text(job, d, o->out);
      return 0;
    };
  });
}

}  // namespace polarcam::cli
