#include "app/operator_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string_view>

#include "app/analysis_report.hpp"
#include "app/capacity_report.hpp"
#include "app/html.hpp"
#include "app/job_capacity.hpp"
#include "app/job_placement.hpp"
#include "app/report_figures.hpp"
#include "cam/error.hpp"
#include "optimize/error_metrics.hpp"
#include "optimize/pareto.hpp"

#ifndef POLARCAM_VERSION
#define POLARCAM_VERSION "0.0.0"
#endif

namespace polarcam::cli {
namespace {

std::string g(double v, int prec = 4) { return std::isfinite(v) ? fmt::format("{:.{}g}", v, prec) : "infinite"; }
std::string mm(double m, int prec = 4) { return g(m * 1e3, prec) + " mm"; }
std::string cms(double v, int prec = 4) { return g(v * 1e2, prec) + " cm/s"; }
std::string pct(double v) { return g(100.0 * v, 3) + " %"; }

// Both a step sink for the error meters and a log of the steps (for the magnified staircase).
class Tee final : public StepSink {
 public:
  Tee(ErrorMeters& m, std::vector<uint8_t>& log) : m_(m), log_(log) {}
  void step(int axis, int dir, int64_t t) override {
    m_.step(axis, dir, t);
    log_.push_back(static_cast<uint8_t>(axis | (dir > 0 ? 2 : 0)));
  }

 private:
  ErrorMeters& m_;
  std::vector<uint8_t>& log_;
};

struct Candidate {
  std::string name;
  Placement placement;
  double area = -1.0;  // m^2
  std::optional<CaseResult> dyn;
};

std::string placement_text(const Placement& p) {
  return fmt::format("C = {}, beta = {} rad", mm(p.C, 6), g(p.beta, 6));
}

std::string load_text(const Job& job) {
  const LoadSpec& l = job.load;
  std::string s;
  switch (l.kind) {
    case LoadKind::none: s = "none (the carriage and arm only)"; break;
    case LoadKind::inertial: s = fmt::format("inertial: {} kg added to the carriage", g(l.mass)); break;
    case LoadKind::grinding:
      s = fmt::format("grinding: depth of cut {}, width {}, wheel speed {} m/s, k_c {} N/m^2, c1 {}",
                      mm(l.grinding.depth), mm(l.grinding.width), g(l.grinding.wheel_speed), g(l.grinding.k_c),
                      g(l.grinding.c1));
      break;
    case LoadKind::force:
      s = fmt::format("a tool force of {} N against the travel and {} N off the material", g(l.force.tangential),
                      g(l.force.normal));
      break;
  }
  if (l.kind != LoadKind::inertial && l.mass > 0.0) s += fmt::format(", {} kg added to the carriage", g(l.mass));
  return s;
}

std::vector<std::string> candidate_row(const Candidate& c, double limit) {
  std::vector<std::string> r = {c.name, mm(c.placement.C, 6), g(c.placement.beta, 6),
                                c.area >= 0.0 ? g(c.area * 1e6, 5) : "-"};
  if (c.dyn) {
    const TorqueAnalysis& a = c.dyn->analysis;
    r.push_back(g(a.radial.ratio.value, 4));
    r.push_back(g(a.angular.ratio.value, 4));
    r.push_back(g(a.balanced.value, 4));
    const double w = worst_torque_ratio(a);
    r.push_back(c.dyn->verdict.go ? "GO" : (w > limit ? "NO-GO (torque)" : "NO-GO (step rate)"));
  } else {
    r.insert(r.end(), {"-", "-", "-", "-"});
  }
  return r;
}

}  // namespace

OperatorReport operator_report(const Job& job, const ReportOptions& o) {
  const std::string name = std::filesystem::path(job.file).filename().string();
  const int threads = o.threads > 0 ? o.threads : default_threads();

  // --- the tape: digitize once, with the error meters and a log of the steps
  const ToolPathPtr path = make_job_path(job);
  PolarTrack track;
  ErrorMeters meters;
  Staircase st;
  DigitizeResult dig;
  ErrorMetrics err;
  try {
    track = PolarTrack::build(*path);
    const SpeedProfilePtr prof = make_job_profile(job, track.length());
    meters.reset(*path, track, job.grid, job.optimize.segments);
    Tee tee(meters, st.steps);
    dig = digitize(track, job.grid, job.motion.rule, *prof, &tee);
    st.n0 = dig.start_n;
    st.m0 = dig.start_m;
    err = meters.finish(dig.start_n, dig.start_m);
  } catch (const InputError& e) {
    throw InputError(job.file + ": " + e.what());
  }

  // --- the dynamics at the job's placement, its capacity
  const PreparedDynamics prep = prepare_dynamics(job);
  AnalysisOptions ao;
  const CaseResult dyn = analyze_case(job, prep, DynamicsCase{std::nullopt, job.load}, ao, true);
  const JobCapacity cap = job_capacity(job, prep, std::nullopt, load_measure(job.load) == LoadMeasure::none ? 0 : o.curve_points);
  const double limit = dyn.verdict.limit;

  // --- the pole study: survey, balanced optimum, least area within the torque limit
  PlacementOptions po = job.optimize;
  po.objective = PoleObjective::area;
  po.pareto = false;
  po.torque_limit = false;
  po.threads = threads;
  if (o.max_evaluations > 0) po.max_evaluations = o.max_evaluations;
  const PoleProblem prob = job_pole_problem(job, po, true);
  PoleSurvey survey;
  std::vector<Candidate> cands;
  std::string limited_note;
  std::optional<Placement> limited;
  try {
    survey = survey_poles(prob, feasible_box(prob, search_box(prob), 41, threads), o.map_size, o.map_size, threads);
    cands.push_back({"this job", job.placement, job_area(job, job.placement), dyn});
    {
      PoleProblem pb = prob;
      pb.objective = PoleObjective::balanced;
      PlacementOptions ob = po;
      ob.objective = PoleObjective::balanced;
      const PlacementResult r = optimize_placement(pb, job.placement, ob);
      cands.push_back({"balanced torque", r.placement, job_area(job, r.placement), job_dynamics_at(job, r.placement)});
    }
    {
      PoleProblem pl = prob;
      pl.torque_limit = limit;
      try {
        const PlacementResult r = optimize_placement(pl, job.placement, po);
        limited = r.placement;
        cands.push_back({"least area error within the torque limit", r.placement, job_area(job, r.placement),
                         job_dynamics_at(job, r.placement)});
      } catch (const InputError& e) {
        limited_note = e.what();
      }
    }
  } catch (const InputError& e) {
    const std::string w = e.what();
    throw InputError(w.rfind(job.file, 0) == 0 ? w : job.file + ": " + w);
  }
  // the front: the survey's non-dominated poles and the candidates
  std::vector<ParetoPoint> pts;
  for (int iy = 0; iy < survey.ny; ++iy)
    for (int ix = 0; ix < survey.nx; ++ix)
      pts.push_back({survey.pole(ix, iy), {}, survey.cells[static_cast<size_t>(iy) * survey.nx + ix], "survey"});
  std::vector<Vec2> cpoles;
  for (const Candidate& c : cands) cpoles.push_back(c.placement.pole());
  const std::vector<PoleValue> cvals = evaluate_poles(prob, cpoles, threads);
  std::vector<ParetoPoint> cpts;
  for (size_t i = 0; i < cands.size(); ++i) {
    cpts.push_back({cpoles[i], cands[i].placement, cvals[i], cands[i].name});
    pts.push_back(cpts.back());
  }
  const std::vector<ParetoPoint> front = non_dominated(pts);

  // ---------------------------------------------------------------- the page
  html::Report rep("Job report: " + name);
  rep.paragraph("Read this before running the job on the machine. It says whether the machine's stepping motors can "
                "drive the job without losing steps (GO / NO-GO), how accurately the machine will follow the "
                "contour, how much load and speed the drives could take, and whether another placement of the "
                "contour would be better. Generated by polarcam " POLARCAM_VERSION " from " + name + ".");

  // verdict
  rep.heading(2, "Verdict", "verdict");
  const Verdict& v = dyn.verdict;
  const char* axis = v.axis == 0 ? "radial" : "angular";
  std::string headline;
  if (v.go)
    headline = "GO: both drives can carry this job";
  else if (v.failure == Failure::step_rate)
    headline = fmt::format("NO-GO: the {} motor would have to step faster than it can", axis);
  else
    headline = fmt::format("NO-GO: the {} drive would lose steps", axis);
  std::string detail = verdict_line(job, dyn);  // analyze's line; the headline already says GO or NO-GO
  for (const char* prefix : {"NO-GO: ", "GO: "})
    if (detail.rfind(prefix, 0) == 0) {
      detail.erase(0, std::string_view(prefix).size());
      break;
    }
  if (!detail.empty()) detail[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(detail[0])));
  rep.verdict(v.go, headline, detail);
  rep.table({"drive", "largest torque ratio", "limit", "share of the limit used", "margin"},
            {{"radial (carriage along the arm)", g(v.radial.ratio), g(limit), pct(v.radial.ratio / limit),
              pct(v.radial.margin)},
             {"angular (arm about the pole)", g(v.angular.ratio), g(limit), pct(v.angular.ratio / limit),
              pct(v.angular.margin)}},
            "Torque ratio = torque the drive needs / torque its motor can give at that speed (pull-out torque). "
            "The job passes when both stay within 1 / safety factor.");
  {
    std::vector<std::string> items;
    const auto fu = usable_speed_factor(cap);
    const char* unit = load_display_unit(cap.measure);
    if (!v.go) {
      if (fu && *fu < 1.0)
        items.push_back(fmt::format("Lower the speed: run at {} or slower (now {}).", cms(*fu * cap.top_speed, 4),
                                    cms(cap.top_speed, 4)));
      else if (!fu)
        items.push_back("No lower speed helps: the load alone is too much for the drives.");
      if (limited) {
        const Candidate& c = cands.back();
        items.push_back(fmt::format(
            "Or move the contour: put the machine pole at {} from the contour pole (area error {} mm^2, now {} "
            "mm^2); `polarcam optimize {} --objective area --torque-limit --write-job moved.toml` writes that job.",
            placement_text(c.placement), g(c.area * 1e6, 4), g(cands.front().area * 1e6, 4), name));
      } else {
        items.push_back("No placement of the contour on the work area keeps every torque ratio within the limit at "
                        "this speed and load.");
      }
      if (cap.measure != LoadMeasure::none) {
        if (cap.load_cap.value)
          items.push_back(fmt::format("Or reduce the {} to {} {} (now {} {}).", load_display_name(cap.measure),
                                      g(load_display(job, cap.measure, *cap.load_cap.value), 4), unit,
                                      g(load_display(job, cap.measure, cap.load_at_job), 4), unit));
        else
          items.push_back(fmt::format("No {} passes at this speed: lower the speed as well.",
                                      load_display_name(cap.measure)));
      }
    } else {
      if (fu)
        items.push_back(fmt::format("Speed: the job still passes up to {}{} (now {}).", cms(*fu * cap.top_speed, 4),
                                    cap.speed_cap.capped ? " or more" : "", cms(cap.top_speed, 4)));
      if (cap.measure != LoadMeasure::none && cap.load_cap.value)
        items.push_back(fmt::format("Load: up to {} {} of {} at this speed{} (now {} {}).",
                                    g(load_display(job, cap.measure, *cap.load_cap.value), 4), unit,
                                    load_display_name(cap.measure), cap.load_cap.capped ? " or more" : "",
                                    g(load_display(job, cap.measure, cap.load_at_job), 4), unit));
    }
    if (!dyn.analysis.corners.empty())
      items.push_back(fmt::format("Caution: the path has {} sharp corner(s) where the drives' speeds jump; the model "
                                  "does not cover them. Slow down there or round them.",
                                  dyn.analysis.corners.size()));
    std::string ul = std::string("<p><strong>") + (v.go ? "Headroom" : "What to do") + "</strong></p>\n<ul>\n";
    for (const auto& it : items) ul += "<li>" + html::escape(it) + "</li>\n";
    rep.raw(ul + "</ul>\n");
  }

  // the job
  rep.heading(2, "The job", "job");
  rep.table({"item", "value"},
            {{"job file", name},
             {"contour", job.contour->name() + (job.contour->closed() ? " (closed)" : " (open)")},
             {"machine", job.machine_name.empty() ? "(unnamed)" : job.machine_name},
             {"placement", placement_text(job.placement) + " (the machine pole seen from the contour's own origin)"},
             {"tool", fmt::format("radius {}, tool centre {} of the travel", mm(job.tool.radius), prep.side > 0 ? "left" : "right")},
             {"speed", dyn.speed ? cms(*dyn.speed) : "speed table"},
             {"load", load_text(job)},
             {"safety factor", fmt::format("{} (every torque ratio must stay within {})", g(job.safety_factor), g(limit))},
             {"stepping rule", to_string(job.motion.rule)}});

  // work area
  rep.heading(2, "Where the contour sits", "workarea");
  const Vec2 wc = err.deviation_at;
  const double rw = std::max(norm(wc), job.grid.dr);
  const double half = std::max(12.0 * job.grid.dr, 8.0 * rw * job.grid.dtheta);
  rep.figure(workarea_figure(job, *path, st, wc, half),
             "Left: the tool-centre path on the machine's work area (the region the arm and carriage can reach), "
             "with the machine pole (the arm's pivot) and the contour's own origin. Right: the circled spot "
             "magnified, at the largest deviation. The machine cannot follow the curve exactly: it moves in steps, "
             "straight along the arm (radial steps) and on arcs about the pole (angular steps), so it traces a "
             "staircase around the contour.",
             "the contour on the work area, and the staircase magnified");

  // the tape
  rep.heading(2, "The step tape", "tape");
  const MachineModel& mm_ = *job.dynamics;
  rep.table({"", "radial (carriage)", "angular (arm)"},
            {{"steps (out + in / anticlockwise + clockwise)",
              fmt::format("{} ({} + {})", dig.radial.steps(), dig.radial.plus, dig.radial.minus),
              fmt::format("{} ({} + {})", dig.angular.steps(), dig.angular.plus, dig.angular.minus)},
             {"resolution", mm(job.grid.dr, 4), fmt::format("{} rad ({} steps per turn)", g(job.grid.dtheta, 4),
                                                             job.grid.steps_per_rev)},
             {"mean tape step rate", g(static_cast<double>(dig.radial.steps()) / dig.duration_s, 4) + " steps/s",
              g(static_cast<double>(dig.angular.steps()) / dig.duration_s, 4) + " steps/s"},
             {"highest tape step rate", g(dig.radial.max_rate_hz, 4) + " steps/s", g(dig.angular.max_rate_hz, 4) + " steps/s"},
             {"highest motor step rate (limit)",
              fmt::format("{} Hz ({})", g(dyn.analysis.radial.step_rate.value, 4),
                          mm_.radial.max_step_rate ? g(*mm_.radial.max_step_rate, 4) + " Hz" : "none given"),
              fmt::format("{} Hz ({})", g(dyn.analysis.angular.step_rate.value, 4),
                          mm_.angular.max_step_rate ? g(*mm_.angular.max_step_rate, 4) + " Hz" : "none given")}},
            fmt::format("{} steps in all; the job takes {} s for {} of path.", dig.radial.steps() + dig.angular.steps(),
                        g(dig.duration_s, 5), mm(dig.path_length_m, 5)));

  // accuracy
  rep.heading(2, "Accuracy", "accuracy");
  rep.table({"measure", "value", "what it means"},
            {{"area error", g(err.area.area_m2 * 1e6, 5) + " mm^2",
              "the area between the contour and the machine's staircase, summed over the whole path"},
             {"largest deviation", mm(err.deviation_max_m, 4),
              fmt::format("the farthest the staircase strays from the contour (at {}, {} from the machine pole)",
                          mm(err.deviation_at.x, 5), mm(err.deviation_at.y, 5))},
             {"bound of Eq. 4.1", mm(err.deviation_eq41_m, 4),
              "one angular step at the path's largest radius (or one radial step, whichever is larger)"},
             {"F1 (thesis's surrogate)", g(err.f_counts.F1, 4), "smaller is better; compare placements only"}});

  // torque
  rep.heading(2, "Torque needed and available", "torque");
  rep.figure(torque_figure(job, dyn),
             "For each drive, along the path: the torque the move needs (orange), the torque its stepping motor can give "
             "at the step rate there (green, the pull-out torque; it falls as the motor steps faster), and the limit "
             "with the safety factor (dashed). Where the orange curve rises above the dashed one, the job is NO-GO.",
             "torque needed and available along the path");
  {
    std::vector<std::vector<std::string>> rows;
    for (int a = 0; a < 2; ++a) {
      const AxisExtremes& e = a == 0 ? dyn.analysis.radial : dyn.analysis.angular;
      const AxisDemand& d = a == 0 ? e.ratio.at.radial : e.ratio.at.angular;
      rows.push_back({a == 0 ? "radial" : "angular", g(e.ratio.value),
                      fmt::format("{} along the path (t = {} s, theta = {} rad, r = {})", mm(e.ratio.at.s), g(e.ratio.at.t),
                                  g(e.ratio.at.theta), mm(e.ratio.at.r)),
                      g(std::abs(d.torque)) + " N m", g(d.pullout) + " N m", g(d.step_rate) + " Hz"});
    }
    rep.table({"drive", "largest ratio", "where", "needed", "available", "motor step rate"}, rows);
  }

  // capacity
  rep.heading(2, "Capacity: how much load and speed the drives could take", "capacity");
  {
    const SpeedCapacity& sc = cap.speed_cap;
    std::vector<std::vector<std::string>> rows;
    rows.push_back({"speed at which a torque ratio reaches the limit",
                    sc.factor ? cms(*sc.factor * cap.top_speed, 5) + (sc.capped ? " or more" : "") : "none passes"});
    rows.push_back({"speed at which a motor reaches its top step rate",
                    sc.step_rate_factor ? cms(*sc.step_rate_factor * cap.top_speed, 5) : "no limit given"});
    if (cap.measure != LoadMeasure::none)
      rows.push_back({fmt::format("largest {} at {}", load_display_name(cap.measure), cms(cap.load_speed)),
                      cap.load_cap.value ? g(load_display(job, cap.measure, *cap.load_cap.value), 5) + " " +
                                               load_display_unit(cap.measure) + (cap.load_cap.capped ? " or more" : "")
                                         : "none passes"});
    rep.table({"", "value"}, rows, "At the job's placement; the other quantity held at the job's value.");
    if (!cap.curve.empty())
      rep.figure(capacity_figure(job, cap),
                 fmt::format("The largest {} the drives can carry at each speed (the torque ratios then reach the "
                             "limit somewhere on the path), up to the speed at which a motor reaches its top "
                             "step rate (dashed). Any point on or below the curve is safe; the circle is this job.",
                             load_display_name(cap.measure)),
                 "capacity curve");
  }

  // pole
  rep.heading(2, "Where to put the contour", "pole");
  rep.paragraph(
      "The same contour can be placed anywhere the machine reaches. The placement changes both the accuracy (the "
      "staircase is finer near the pole) and the torques (how the motion splits between the two drives). The map "
      "shows the area error for every position of the machine pole relative to the contour's origin (blank: the "
      "contour would leave the work area); crosses mark positions where a torque ratio exceeds the limit, and the "
      "coloured line is where the worst one equals it.");
  std::vector<PoleMark> marks = {{job.placement.pole(), "this job", 1, 4}};
  if (cands.size() > 1) marks.push_back({cands[1].placement.pole(), "balanced torque", 2, 2});
  if (limited) marks.push_back({cands.back().placement.pole(), "least area within the limit", 0, 3});
  Job at0 = job;
  at0.placement = Placement{0.0, 0.0};
  rep.figure(pole_map_figure(job, survey, limit, segment_points(*make_job_path(at0), 1500), marks),
             "Area error over machine-pole positions, the torque limit, and the placements below.", "pole map");
  {
    std::vector<std::vector<std::string>> rows;
    for (const Candidate& c : cands) rows.push_back(candidate_row(c, limit));
    rep.table({"placement", "C", "beta (rad)", "area error (mm^2)", "radial ratio", "angular ratio",
               "balanced objective", "verdict"},
              rows,
              "Balanced torque: the placement where the busier drive is least loaded relative to the other (the "
              "thesis's objective: the largest along the path of (R + A) / (1 - |R - A|), R and A the two torque "
              "ratios). Least area error within the torque limit: the most accurate placement the drives can carry.");
    if (!limited_note.empty()) rep.paragraph("Least area error within the torque limit: " + limited_note + ".");
  }

  // trade-off
  rep.heading(2, "Accuracy against torque", "tradeoff");
  std::vector<std::pair<ParetoPoint, PoleMark>> tmarks;
  for (size_t i = 0; i < cpts.size() && i < marks.size(); ++i) tmarks.push_back({cpts[i], marks[i]});
  rep.figure(tradeoff_figure(survey, front, limit, tmarks),
             "Each grey dot is a placement: its area error against its worst torque ratio. The blue line joins the "
             "placements no other beats in both (the Pareto front): moving along it buys accuracy with torque. "
             "Placements right of the dashed line are NO-GO at this speed and load.",
             "area error against worst torque ratio");
  {
    std::vector<std::vector<std::string>> rows;
    const size_t step = std::max<size_t>(1, (front.size() + 11) / 12);
    for (size_t i = 0; i < front.size(); i += step) {
      const ParetoPoint& x = front[i];
      const Placement pl{norm(x.pole), std::fmod(std::atan2(x.pole.y, x.pole.x) + 2.0 * std::numbers::pi,
                                                 2.0 * std::numbers::pi)};
      rows.push_back({mm(pl.C, 6), g(pl.beta, 6), g(x.v.area_m2 * 1e6, 5), g(x.v.torque.worst, 4),
                      x.v.torque.worst <= limit ? "within" : "over"});
    }
    rep.table({"C", "beta (rad)", "area error (mm^2)", "worst torque ratio", "torque limit"}, rows,
              "Points of the front (every " + std::to_string(step) + ")");
  }

  // glossary
  rep.heading(2, "How to read this report", "glossary");
  rep.raw(
      "<dl>\n"
      "<dt>Machine pole, contour pole, C and beta</dt><dd>The arm swings about the machine pole. The contour is "
      "drawn about its own origin, the contour pole. The placement puts the machine pole at distance C from the "
      "contour pole, in the direction beta.</dd>\n"
      "<dt>Radial and angular drives</dt><dd>The radial drive moves the carriage (and tool) along the arm through a "
      "screw; the angular drive swings the arm through a worm gear. Each is a stepping motor without feedback: if "
      "it is asked for more torque than it has, it loses steps and every later step lands in the wrong place.</dd>\n"
      "<dt>Pull-out torque</dt><dd>The largest load torque a stepping motor carries at a given step rate without "
      "losing steps; it falls as the motor steps faster.</dd>\n"
      "<dt>Torque ratio, safety factor</dt><dd>Torque needed divided by pull-out torque. Above 1 the motor loses "
      "steps; the job is GO when both ratios stay within 1 / safety factor everywhere on the path and no motor "
      "must step faster than its drive allows.</dd>\n"
      "<dt>Area error, deviation</dt><dd>How far the machine's staircase strays from the contour: the area between "
      "them, and the largest distance.</dd>\n"
      "<dt>Capacity</dt><dd>The largest speed, and the largest load, at which the worst torque ratio just reaches "
      "the limit.</dd>\n"
      "</dl>\n"
      "<p>The model: A. Fahim's polar contouring system (1983), chapters 4-6, as polarcam implements it "
      "(docs/dynamics.md, docs/area-error.md, docs/optimum-loading.md). The torque model matched measurements "
      "within about 10 %: a safety factor of 1.2 or more is advisable.</p>\n");

  OperatorReport out;
  out.html = rep.str();
  out.go = v.go;
  return out;
}

}  // namespace polarcam::cli
