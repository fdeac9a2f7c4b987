// polarcam optimize JOB.toml [--objective area|f1|balanced|pareto] [--torque-limit] [--method nlopt|hooke-jeeves]
//                   [--hold none|C|beta] [--pole-outside] [--json] [--map FILE.csv] [--map-image FILE.png|.svg]
//                   [--write-job FILE.toml]
// Pole placement for least contouring error (Ch. 4, docs/area-error.md), for balanced axis torque (Sec. 6.6.2), for
// least error within the torque limit, and the trade-off front between the two (docs/optimum-loading.md).
#include <chrono>
#include <cmath>
#include <optional>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "job/job.hpp"
#include "job/pattern.hpp"
#include "pipeline/job_placement.hpp"
#include "job/job_write.hpp"
#include "io/output.hpp"
#include "io/progress.hpp"
#include "report/pole_map.hpp"
#include "cam/error.hpp"
#include "metrics/f1.hpp"
#include "optimize/pareto.hpp"

namespace polarcam::cli {
namespace cmd_optimize {  // named, not anonymous: the command files are compiled together (unity build)

using json = nlohmann::ordered_json;

std::string fmt(double v, int prec = 6) { return significant(v, prec); }

json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

struct Opts {
  std::string job, objective, method, hold, map, map_image, write_job;
  PatternArgs pattern;
  bool json = false, pole_outside = false, torque_limit = false, quiet = false;
  int segments = 0, max_evaluations = 0, threads = -1, map_size = 41, levels = 6, survey = 25;
  SafetyFactor safety_factor;
  // options that apply to some objectives or outputs only: refused where they would be ignored
  CLI::Option *method_opt = nullptr, *segments_opt = nullptr, *levels_opt = nullptr, *survey_opt = nullptr,
              *map_size_opt = nullptr, *speed_opt = nullptr;
};

// The dynamics at a placement as `analyze` reports them (the balanced objective, the worst ratios, the verdict).
void torque_fields(json& j, const CaseResult& c) {
  const TorqueAnalysis& a = c.analysis;
  j["max_torque_ratio_radial"] = num(a.radial.ratio.value);
  j["max_torque_ratio_angular"] = num(a.angular.ratio.value);
  j["worst_torque_ratio"] = num(worst_torque_ratio(a));
  j["max_ratio_sum"] = num(a.ratio_sum.value);
  j["balanced_objective"] = num(a.balanced.value);
  j["verdict"] = c.verdict.go ? "GO" : "NO-GO";
}

std::string torque_text(const CaseResult& c) {
  const TorqueAnalysis& a = c.analysis;
  std::ostringstream os;
  os << "max torque ratio radial " << fmt(a.radial.ratio.value, 4) << ", angular " << fmt(a.angular.ratio.value, 4)
     << "; balanced objective "
     << (std::isfinite(a.balanced.value) ? fmt(a.balanced.value, 6) : std::string("infinite")) << "; "
     << (c.verdict.go ? "GO" : "NO-GO") << " (limit " << fmt(c.verdict.limit, 4) << ")";
  return os.str();
}

int run_pareto(const Job& job, PlacementOptions opt, const Opts& o) {
  PoleProblem problem = job_pole_problem(job, opt, true);
  ParetoOptions po;
  po.levels = o.levels;
  po.survey = o.survey;
  po.threads = opt.threads;
  const auto t0 = std::chrono::steady_clock::now();
  const ParetoResult r = in_file(job.file, [&] {
    TerminalBar bar("optimize", o.quiet);  // erased before the output
    return pareto_front(problem, job.placement, opt, po, bar.callback());
  });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double limit = 1.0 / job.safety_factor;
  // the least area error within the limit, among the front's points
  const ParetoPoint* within = nullptr;
  for (const ParetoPoint& x : r.front)
    if (x.v.torque.worst <= limit && (!within || x.v.area_m2 < within->v.area_m2)) within = &x;
  auto point_json = [&](const ParetoPoint& x) {
    json p;
    p["C_mm"] = x.placement.C * 1e3;
    p["beta_rad"] = x.placement.beta;
    p["pole_x_mm"] = x.pole.x * 1e3;
    p["pole_y_mm"] = x.pole.y * 1e3;
    p["area_error_mm2"] = x.v.area_m2 * 1e6;
    p["objective"] = num(x.v.torque.balanced);
    p["max_torque_ratio_radial"] = num(x.v.torque.ratio_radial);
    p["max_torque_ratio_angular"] = num(x.v.torque.ratio_angular);
    p["worst_torque_ratio"] = num(x.v.torque.worst);
    p["within_limit"] = x.v.torque.worst <= limit && x.v.torque.rate_over <= 1.0;
    p["source"] = x.source;
    return p;
  };
  if (o.json) {
    json j;
    j["job"] = job.file;
    j["objective_name"] = "pareto";
    j["rule"] = to_string(job.motion.rule);
    j["safety_factor"] = job.safety_factor;
    j["ratio_limit"] = limit;
    j["points"] = json::array();
    for (const ParetoPoint& x : r.front) j["points"].push_back(point_json(x));
    j["least_area_within_limit"] = within ? point_json(*within) : json(nullptr);
    j["survey_size"] = r.survey.nx;
    j["evaluations"] = r.evaluations;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::ostringstream os;
  os << "polarcam optimize " << job.file << " (Pareto front of area error and worst torque ratio, rule "
     << to_string(job.motion.rule) << ")\n";
  os << "       C (mm)   beta (rad)   area error (mm^2)   worst ratio   radial    angular   from\n";
  for (const ParetoPoint& x : r.front) {
    char line[200];
    std::snprintf(line, sizeof line, "  %11.4f   %10.6f   %17.5f   %11.5f   %7.5f   %7.5f   %s%s\n",
                  x.placement.C * 1e3, x.placement.beta, x.v.area_m2 * 1e6, x.v.torque.worst,
                  x.v.torque.ratio_radial, x.v.torque.ratio_angular, x.source.c_str(),
                  x.v.torque.worst <= limit ? "" : "  (over the limit)");
    os << line;
  }
  if (within)
    os << "  least area error within the torque limit " << fmt(limit, 4) << ": C = " << fmt(within->placement.C * 1e3, 9)
       << " mm, beta = " << fmt(within->placement.beta, 9) << " rad, " << fmt(within->v.area_m2 * 1e6) << " mm^2\n";
  else
    os << "  no pole of the front keeps every torque ratio within " << fmt(limit, 4) << "\n";
  os << "  search      " << r.evaluations << " evaluations in " << fmt(wall, 3) << " s\n";
  std::cout << os.str();
  return 0;
}

int run(const Opts& o) {
  // every output checked before any work
  if (!o.map.empty()) check_output_path(o.map);
  if (!o.map_image.empty()) plot::check_plot_path(o.map_image);
  if (!o.write_job.empty()) check_output_path(o.write_job);
  // a pattern's search for the least area error or F1 is geometry: it needs no speed (a job file's objective may
  // come from its [optimize] table, so a job's --speed is checked once that is known, below)
  const bool speed_used = !is_pattern_file(o.job) || o.objective == "balanced" || o.objective == "pareto" || o.torque_limit;
  Job job = load_job_input(o.job, o.pattern, 1e-4, speed_used);
  apply_safety_factor(o.safety_factor, job);
  PlacementOptions opt = job.optimize;
  if (!o.objective.empty()) {
    opt.pareto = o.objective == "pareto";
    if (!opt.pareto)
      opt.objective = o.objective == "area" ? PoleObjective::area
                                            : (o.objective == "f1" ? PoleObjective::f1 : PoleObjective::balanced);
  }
  if (!o.method.empty()) opt.method = o.method == "nlopt" ? PoleMethod::nlopt : PoleMethod::hooke_jeeves;
  if (!o.hold.empty()) opt.hold = o.hold == "C" ? PoleHold::C : (o.hold == "beta" ? PoleHold::beta : PoleHold::none);
  if (o.pole_outside) opt.pole_outside = true;
  if (o.torque_limit) opt.torque_limit = true;
  if (o.segments > 0) opt.segments = o.segments;
  if (o.max_evaluations > 0) opt.max_evaluations = o.max_evaluations;
  if (o.threads >= 0) opt.threads = o.threads;
  if (opt.pareto) {
    if (!o.map.empty() || !o.map_image.empty() || !o.write_job.empty())
      throw InputError("--map, --map-image and --write-job go with one optimum, not with --objective pareto");
    if (o.torque_limit)
      throw InputError("the Pareto front spans every torque ratio; its limit is 1 / safety factor", "--torque-limit");
    if (option_given(o.method_opt)) throw InputError("the Pareto front has a search of its own", "--method");
    if (option_given(o.segments_opt)) throw InputError("applies to --objective f1", "--segments");
    if (option_given(o.map_size_opt)) throw InputError("sizes --map or --map-image, which the Pareto front does not draw", "--map-size");
    return run_pareto(job, opt, o);
  }
  const bool dynamics = is_torque_objective(opt.objective) || opt.torque_limit;
  if (option_given(o.levels_opt)) throw InputError("applies to --objective pareto", "--levels");
  if (option_given(o.survey_opt)) throw InputError("applies to --objective pareto", "--survey");
  if (option_given(o.map_size_opt) && o.map.empty() && o.map_image.empty())
    throw InputError("sizes the map: give --map FILE.csv or --map-image FILE.png with it", "--map-size");
  if (option_given(o.segments_opt) && opt.objective != PoleObjective::f1) throw InputError("applies to --objective f1", "--segments");
  if (!dynamics) {
    // the area error and F1 are geometry: neither the speed nor the torque limits enter them
    const char* why = "the area error and F1 do not depend on it: it applies with --torque-limit, --objective balanced "
                      "or pareto";
    if (option_given(o.safety_factor.option)) throw InputError(why, "--safety-factor");
    if (option_given(o.speed_opt) && !is_pattern_file(o.job)) throw InputError(why, "--speed");
  }

  const PoleProblem problem = job_pole_problem(job, opt, dynamics);
  const auto t0 = std::chrono::steady_clock::now();
  // one bar for the search and the map (the search half of it when a map is drawn), erased before the output
  std::optional<TerminalBar> bar(std::in_place, "optimize", o.quiet);
  const bool mapped = !o.map.empty() || !o.map_image.empty();
  const Progress progress = bar->callback();
  const PlacementResult r = in_file(job.file, [&] {
    return optimize_placement(problem, job.placement, opt, progress_part(progress, 0.0, mapped ? 0.5 : 1.0));
  });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double area = job_area(job, r.placement);
  const double start_area = r.start.feasible() ? job_area(job, job.placement) : -1.0;
  // the dynamics at the optimum and at the job's placement, through the production pipeline
  std::optional<CaseResult> dyn, dyn_start;
  if (dynamics) {
    dyn = job_dynamics_at(job, r.placement);
    if (r.start.geometry_margin >= 0.0 && r.start.computed) dyn_start = job_dynamics_at(job, job.placement);
  }
  double objective = 0.0;
  switch (opt.objective) {
    case PoleObjective::area: objective = area * 1e6; break;
    case PoleObjective::f1: objective = r.f1; break;
    case PoleObjective::balanced: objective = dyn->analysis.balanced.value; break;
    case PoleObjective::torque: objective = worst_torque_ratio(dyn->analysis); break;
  }
  std::string name = to_string(opt.objective);
  if (opt.torque_limit) name += " (torque-limited)";

  // outputs: all or nothing, and only after the search succeeded
  std::string csv, note;
  plot::Figure fig;
  const Job at0 = [&] {
    Job j = job;
    j.placement = Placement{0.0, 0.0};
    return j;
  }();
  if (!o.map.empty() || !o.map_image.empty()) {
    const int threads = opt.threads > 0 ? opt.threads : default_threads();
    const SearchBox box = feasible_box(problem, search_box(problem), 65, threads, progress_part(progress, 0.5, 0.55));
    const ObjectiveMap m = objective_map(problem, box, o.map_size, o.map_size, threads, progress_part(progress, 0.55, 1.0));
    if (!o.map.empty()) csv = map_csv(m, opt.objective);
    if (!o.map_image.empty()) {
      const std::string what = opt.objective == PoleObjective::area  ? "exact area error"
                               : opt.objective == PoleObjective::f1 ? "F1"
                                                                      : "balanced-torque objective";
      fig = map_figure(m, opt.objective, segment_points(*make_job_path(at0), 2000), job.placement, r,
                       job.contour_kind + ": " + what + " over machine-pole positions");
    }
  }
  bar.reset();
  std::vector<std::pair<std::string, std::string>> files;
  if (!o.map.empty()) files.emplace_back(o.map, csv);
  if (!o.map_image.empty()) files.emplace_back(o.map_image, plot::render(fig, plot::plot_format(o.map_image)));
  if (!o.write_job.empty()) {
    note = "written by polarcam optimize from " + std::filesystem::path(job.file).filename().string() +
           ": objective " + name + ", method " + to_string(r.method) + ", area error " + fmt(area * 1e6, 9) + " mm^2";
    files.emplace_back(o.write_job, job_with_placement(job.file, r.placement, o.write_job, note));
  }
  write_files_atomic(files);

  if (o.json) {
    json j;
    j["job"] = job.file;
    j["objective_name"] = to_string(opt.objective);
    j["torque_limit"] = opt.torque_limit ? json(1.0 / job.safety_factor) : json(nullptr);
    j["method"] = to_string(r.method);
    j["rule"] = to_string(job.motion.rule);
    j["hold"] = to_string(opt.hold);
    j["pole_outside"] = opt.pole_outside;
    j["C_mm"] = r.placement.C * 1e3;
    j["beta_rad"] = r.placement.beta;
    j["pole_x_mm"] = r.pole.x * 1e3;  // O - O1
    j["pole_y_mm"] = r.pole.y * 1e3;
    j["contour_pole_x_mm"] = -r.pole.x * 1e3;  // O1 seen from the machine pole (Table 4.1's limacon entries)
    j["contour_pole_y_mm"] = -r.pole.y * 1e3;
    j["contour_pole_beta_rad"] = opposite_beta(r.placement);
    j["area_error_mm2"] = area * 1e6;
    j["objective"] = num(objective);
    j["F1"] = r.f1;
    if (dyn) torque_fields(j, *dyn);
    j["margin_mm"] = std::isfinite(r.at.margin) ? json(r.at.margin * 1e3) : json();
    j["evaluations"] = r.evaluations;
    json st;
    st["C_mm"] = job.placement.C * 1e3;
    st["beta_rad"] = job.placement.beta;
    st["feasible"] = r.start.feasible();
    if (start_area >= 0.0) st["area_error_mm2"] = start_area * 1e6;
    st["F1"] = f1_chords(problem.f1_points, job.placement.pole(), job.machine.grid.dr, job.machine.grid.dtheta).F1;
    if (dyn_start) torque_fields(st, *dyn_start);
    j["start"] = st;
    for (const auto& s : r.stages) j["stages"].push_back({{"name", s.name}, {"evaluations", s.evaluations}, {"best", s.best}});
    if (!r.path.empty())
      for (const Vec2& v : r.path) j["path_mm"].push_back({v.x * 1e3, v.y * 1e3});
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::ostringstream os;
  os << "polarcam optimize " << job.file << " (objective " << name << ", method " << to_string(r.method) << ", rule "
     << to_string(job.motion.rule) << ")\n";
  os << "  optimum     C = " << fmt(r.placement.C * 1e3, 9) << " mm, beta = " << fmt(r.placement.beta, 9)
     << " rad (machine pole at x = " << fmt(r.pole.x * 1e3) << " mm, y = " << fmt(r.pole.y * 1e3)
     << " mm from the contour pole)\n";
  os << "             the contour pole seen from the machine pole: beta = " << fmt(opposite_beta(r.placement), 9)
     << " rad (the description Table 4.1 uses for the limacon)\n";
  os << "  area error  " << fmt(area * 1e6, 6) << " mm^2";
  if (start_area >= 0.0) os << " (job's placement: " << fmt(start_area * 1e6, 6) << " mm^2)";
  os << ", F1 " << fmt(r.f1, 5) << "\n";
  if (dyn) {
    os << "  torques     " << torque_text(*dyn) << "\n";
    if (dyn_start) os << "  (job's)     " << torque_text(*dyn_start) << "\n";
  }
  os << "  search      " << r.evaluations << " evaluations in " << fmt(wall, 3) << " s:";
  for (const auto& s : r.stages) os << " " << s.name << " " << s.evaluations << ";";
  os << "\n";
  if (!o.write_job.empty()) os << "  job         " << o.write_job << "\n";
  std::cout << os.str();
  return 0;
}

}  // namespace cmd_optimize

void register_optimize(CLI::App& app, Action& action) {
  using namespace cmd_optimize;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("optimize", "Place the machine pole for least contouring error (exact area error, "
                                               "or the thesis's F1), for balanced axis torque, or show the trade-off "
                                               "between the two");
  c->add_option("job", o->job, "job file (TOML); its [optimize] section gives defaults for these options")->required();
  add_pattern_options(c, o->pattern);
  o->speed_opt = c->get_option("--speed");
  c->add_option("--objective", o->objective,
                "area (exact area error), f1 (the thesis's surrogate), balanced (balanced axis torque, Sec. 6.6.2) or "
                "pareto (area error against the worst torque ratio)")
      ->check(CLI::IsMember({"area", "f1", "balanced", "pareto"}));
  c->add_flag("--torque-limit", o->torque_limit,
              "keep every torque ratio within 1 / safety factor (and every motor within its step-rate limit): with "
              "--objective area, the pole of least area error the drives can carry");
  add_safety_factor_option(c, o->safety_factor);
  o->method_opt = c->add_option("--method", o->method, "nlopt (global + local + sampling) or hooke-jeeves (the thesis's search)")
      ->check(CLI::IsMember({"nlopt", "hooke-jeeves"}));
  c->add_option("--hold", o->hold, "keep C or beta at the job's value (none, C, beta)")
      ->check(CLI::IsMember({"none", "C", "beta"}));
  c->add_flag("--pole-outside", o->pole_outside, "keep the machine pole outside a closed contour");
  o->segments_opt = c->add_option("--segments", o->segments, "F1: segments of the piecewise-linear approximation")->check(CLI::Range(1, 100000));
  c->add_option("--max-evaluations", o->max_evaluations, "objective evaluations (default: from the job's size)")
      ->check(CLI::Range(10, 10000000));
  o->levels_opt = c->add_option("--levels", o->levels, "pareto: torque levels searched between the two ends (default 6)")
      ->check(CLI::Range(0, 100));
  o->survey_opt = c->add_option("--survey", o->survey, "pareto: survey points per side of the pole box (default 25)")
      ->check(CLI::Range(2, 401));
  c->add_option("--threads", o->threads, "threads (default: all cores; the result does not depend on it)")
      ->check(CLI::Range(0, 1024));
  c->add_flag("--json", o->json, "print the result as one JSON object");
  c->add_flag("--quiet", o->quiet, "no progress bar (shown on a terminal only)");
  c->add_option("--map", o->map, "write the objective over pole positions as CSV");
  c->add_option("--map-image", o->map_image, "draw the map (.png or .svg)");
  o->map_size_opt = c->add_option("--map-size", o->map_size, "points per side of the map (default 41)")->check(CLI::Range(2, 2001));
  c->add_option("--write-job", o->write_job, "write the job with the optimal placement to this file");
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
