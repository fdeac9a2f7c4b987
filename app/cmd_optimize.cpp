// polarcam optimize JOB.toml [--objective area|f1] [--method nlopt|hooke-jeeves] [--hold none|C|beta]
//                   [--pole-outside] [--json] [--map FILE.csv] [--map-image FILE.png|.svg] [--write-job FILE.toml]
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "app/job.hpp"
#include "app/job_tape.hpp"
#include "app/job_write.hpp"
#include "app/output.hpp"
#include "app/pole_map.hpp"
#include "cam/error.hpp"
#include "optimize/f1.hpp"

namespace polarcam::cli {
namespace {

std::string fmt(double v, int prec = 6) {
  std::ostringstream os;
  os.precision(prec);
  os << v;
  return os.str();
}

// The exact area error of the job at a placement, through the production pipeline (the job's grid and work area).
double job_area(const Job& job, const Placement& pl) {
  Job j = job;
  j.placement = pl;
  PolarAreaMeter meter;
  const ToolPathPtr path = make_job_path(j);
  PolarTrack track;
  try {
    track = PolarTrack::build(*path);
    meter.reset(track, j.grid);
    auto prof = make_job_profile(j, track.length());
    const DigitizeResult d = digitize(track, j.grid, j.motion.rule, *prof, &meter);
    return meter.finish(d.start_n, d.start_m).area_m2;
  } catch (const InputError& e) {
    throw InputError(job.file + ": at the optimum: " + e.what());
  }
}

// The direction of O1 - O, in [0, 2 pi).
double opposite_beta(const Placement& pl) {
  if (!(pl.C > 0.0)) return 0.0;
  double b = std::fmod(pl.beta + std::numbers::pi, 2.0 * std::numbers::pi);
  if (b < 0.0) b += 2.0 * std::numbers::pi;
  return b;
}

}  // namespace

void register_optimize(CLI::App& app, Action& action) {
  struct Opts {
    std::string job, objective, method, hold, map, map_image, write_job;
    bool json = false, pole_outside = false;
    int segments = 0, max_evaluations = 0, threads = -1, map_size = 41;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("optimize", "Place the machine pole for minimum contouring error (exact area "
                                               "error, or the thesis's F1)");
  c->add_option("job", o->job, "job file (TOML); its [optimize] section gives defaults for these options")->required();
  c->add_option("--objective", o->objective, "area (exact area error) or f1 (the thesis's surrogate)")
      ->check(CLI::IsMember({"area", "f1"}));
  c->add_option("--method", o->method, "nlopt (global + local + sampling) or hooke-jeeves (the thesis's search)")
      ->check(CLI::IsMember({"nlopt", "hooke-jeeves"}));
  c->add_option("--hold", o->hold, "keep C or beta at the job's value (none, C, beta)")
      ->check(CLI::IsMember({"none", "C", "beta"}));
  c->add_flag("--pole-outside", o->pole_outside, "keep the machine pole outside a closed contour");
  c->add_option("--segments", o->segments, "F1: segments of the piecewise-linear approximation")->check(CLI::Range(1, 100000));
  c->add_option("--max-evaluations", o->max_evaluations, "objective evaluations (default: from the job's size)")
      ->check(CLI::Range(10, 10000000));
  c->add_option("--threads", o->threads, "threads (default: all cores; the result does not depend on it)")
      ->check(CLI::Range(0, 1024));
  c->add_flag("--json", o->json, "print the result as one JSON object");
  c->add_option("--map", o->map, "write the objective over pole positions as CSV");
  c->add_option("--map-image", o->map_image, "draw the map (.png or .svg)");
  c->add_option("--map-size", o->map_size, "points per side of the map (default 41)")->check(CLI::Range(2, 2001));
  c->add_option("--write-job", o->write_job, "write the job with the optimal placement to this file");
  c->callback([o, &action] {
    action = [o] {
      const Job job = load_job(o->job);
      PlacementOptions opt = job.optimize;
      if (!o->objective.empty()) opt.objective = o->objective == "area" ? PoleObjective::area : PoleObjective::f1;
      if (!o->method.empty()) opt.method = o->method == "nlopt" ? PoleMethod::nlopt : PoleMethod::hooke_jeeves;
      if (!o->hold.empty()) opt.hold = o->hold == "C" ? PoleHold::C : (o->hold == "beta" ? PoleHold::beta : PoleHold::none);
      if (o->pole_outside) opt.pole_outside = true;
      if (o->segments > 0) opt.segments = o->segments;
      if (o->max_evaluations > 0) opt.max_evaluations = o->max_evaluations;
      if (o->threads >= 0) opt.threads = o->threads;
      for (const std::string* f : {&o->map_image})
        if (!f->empty()) {
          const std::string ext = std::filesystem::path(*f).extension().string();
          if (ext != ".png" && ext != ".svg") throw InputError(*f + ": the map image must be a .png or .svg file");
        }

      // the tool path with the machine pole at the contour pole; the search moves the pole
      Job at0 = job;
      at0.placement = Placement{0.0, 0.0};
      const ToolPathPtr path0 = make_job_path(at0);
      PoleProblem problem;
      try {
        problem = make_pole_problem(path0, job.grid, job.motion.rule, opt.objective, opt.segments, opt.pole_outside);
      } catch (const InputError& e) {
        throw InputError(job.file + ": " + e.what());
      }
      const auto t0 = std::chrono::steady_clock::now();
      PlacementResult r;
      try {
        r = optimize_placement(problem, job.placement, opt);
      } catch (const InputError& e) {
        throw InputError(job.file + ": " + e.what());
      }
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double area = job_area(job, r.placement);
      const double start_area = r.start.feasible() ? job_area(job, job.placement) : -1.0;
      const double objective = opt.objective == PoleObjective::area ? area * 1e6 : r.f1;

      // outputs: all or nothing, and only after the search succeeded
      std::string csv, note;
      plot::Figure fig;
      if (!o->map.empty() || !o->map_image.empty()) {
        const int threads = opt.threads > 0 ? opt.threads : default_threads();
        const SearchBox box = feasible_box(problem, search_box(problem), 65, threads);
        const ObjectiveMap m = objective_map(problem, box, o->map_size, o->map_size, threads);
        if (!o->map.empty()) csv = map_csv(m, opt.objective);
        if (!o->map_image.empty()) {
          const std::string what = opt.objective == PoleObjective::area ? "exact area error" : "F1";
          fig = map_figure(m, opt.objective, segment_points(*path0, 2000), job.placement, r,
                           job.contour_kind + ": " + what + " over machine-pole positions");
        }
      }
      if (!o->map.empty()) write_file_atomic(o->map, csv);
      if (!o->map_image.empty()) plot::save(fig, o->map_image);
      if (!o->write_job.empty()) {
        note = "written by polarcam optimize from " + std::filesystem::path(job.file).filename().string() +
               ": objective " + to_string(opt.objective) + ", method " + to_string(r.method) + ", area error " +
               fmt(area * 1e6, 9) + " mm^2";
        write_file_atomic(o->write_job, job_with_placement(job.file, r.placement, o->write_job, note));
      }

      if (o->json) {
        nlohmann::ordered_json j;
        j["job"] = job.file;
        j["objective_name"] = to_string(opt.objective);
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
        j["objective"] = objective;
        j["F1"] = r.f1;
        j["margin_mm"] = std::isfinite(r.at.margin) ? nlohmann::ordered_json(r.at.margin * 1e3) : nlohmann::ordered_json();
        j["evaluations"] = r.evaluations;
        j["wall_s"] = wall;
        nlohmann::ordered_json st;
        st["C_mm"] = job.placement.C * 1e3;
        st["beta_rad"] = job.placement.beta;
        st["feasible"] = r.start.feasible();
        if (start_area >= 0.0) st["area_error_mm2"] = start_area * 1e6;
        st["F1"] = f1_chords(problem.f1_points, job.placement.pole(), job.grid.dr, job.grid.dtheta).F1;
        j["start"] = st;
        for (const auto& s : r.stages) j["stages"].push_back({{"name", s.name}, {"evaluations", s.evaluations}, {"best", s.best}});
        if (!r.path.empty())
          for (const Vec2& v : r.path) j["path_mm"].push_back({v.x * 1e3, v.y * 1e3});
        std::cout << j.dump(2) << "\n";
        return 0;
      }
      std::ostringstream os;
      os << "polarcam optimize " << job.file << " (objective " << to_string(opt.objective) << ", method "
         << to_string(r.method) << ", rule " << to_string(job.motion.rule) << ")\n";
      os << "  optimum     C = " << fmt(r.placement.C * 1e3, 9) << " mm, beta = " << fmt(r.placement.beta, 9)
         << " rad (machine pole at x = " << fmt(r.pole.x * 1e3) << " mm, y = " << fmt(r.pole.y * 1e3)
         << " mm from the contour pole)\n";
      os << "             the contour pole seen from the machine pole: beta = " << fmt(opposite_beta(r.placement), 9)
         << " rad (the description Table 4.1 uses for the limacon)\n";
      os << "  area error  " << fmt(area * 1e6, 6) << " mm^2";
      if (start_area >= 0.0) os << " (job's placement: " << fmt(start_area * 1e6, 6) << " mm^2)";
      os << ", F1 " << fmt(r.f1, 5) << "\n";
      os << "  search      " << r.evaluations << " evaluations in " << fmt(wall, 3) << " s:";
      for (const auto& s : r.stages) os << " " << s.name << " " << s.evaluations << ";";
      os << "\n";
      if (!o->write_job.empty()) os << "  job         " << o->write_job << "\n";
      std::cout << os.str();
      return 0;
    };
  });
}

}  // namespace polarcam::cli
