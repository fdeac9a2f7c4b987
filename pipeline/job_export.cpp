#include "pipeline/job_export.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/svg_export.hpp"
#include "cam/thr_export.hpp"
#include "cam/thr_file.hpp"
#include "pipeline/job_analysis.hpp"
#include "pipeline/job_tape.hpp"

#include <numbers>

namespace polarcam {
namespace {

std::string mm(double m) { return significant(m * 1e3) + " mm"; }

// The lines that say where a file comes from: the job file's name (not its directory), the contour, the tolerance.
std::vector<std::string> source_lines(const Job& job, const ExportOptions& o) {
  return {"polarcam export of " + std::filesystem::path(job.file).filename().string(),
          "contour: " + job.contour->name(), "tolerance: " + mm(o.tolerance)};
}

double rho_max(const std::vector<ThetaRho>& v) {
  double r = 0;
  for (const ThetaRho& p : v) r = std::max(r, p.rho);
  return r;
}

// Refuses a path that reaches beyond `limit`, naming the limit.
void check_reach(const Job& job, double reach, double limit, const std::string& what) {
  if (reach > limit * (1.0 + 1e-12))
    throw InputError("the path reaches " + mm(reach) + " from the pole, beyond " + what + " (" + mm(limit) + ")", job.file);
}

// The machine's [gcode] table with the export's feed mode, for a path reaching `reach` from the pole; refuses a
// machine without one, a job without a constant speed, the axis feed mode without its feed, a path beyond the table.
GcodeSpec export_gcode_spec(const Job& job, const ExportOptions& o, double reach) {
  if (!job.machine.gcode)
    throw InputError("the machine has no [gcode] table: add one to its machine file (docs/gcode.md)", job.file);
  if (!job.motion.table.empty() || job.motion.rollers)
    throw InputError("G-code export needs a constant speed: give [motion] speed (or --speed), not speed_profile", job.file);
  GcodeSpec spec = *job.machine.gcode;
  if (o.feed_mode) spec.feed_mode = *o.feed_mode;
  if (job.motion.time_optimal && spec.feed_mode != FeedMode::inverse_time)
    throw InputError("a time-optimal schedule needs the inverse-time feed mode (each move its own duration); the "
                     "axis mode feeds at one rate: use --feed-mode inverse-time", job.file);
  if (spec.feed_mode == FeedMode::axis && !(spec.axis_feed > 0.0))
    throw InputError("the axis feed mode needs axis_feed in the machine's [gcode] table", job.file);
  check_reach(job, reach, spec.table_radius, "the [gcode] table radius");
  return spec;
}

// A time-optimal job's theta-rho vertices with a ball speed per segment (docs/time-optimal.md, "Export"). Each
// segment is measured along its spiral at 64 points, the lengths scaled to the schedule's path length (the spiral
// lies within the tolerance of the path, so its length is the path's but for a hair); a segment is cut at those
// points (linear in theta and rho, on the spiral) wherever the schedule's speed changes by more than 5 % along it,
// and each piece gets the smallest speed of the schedule over it, over a stretch a tolerance longer at both ends,
// divided by 1.011, so that the moves' ball speed (within 1 % of it, docs/gcode.md) never exceeds the schedule. A
// piece that reaches a station at rest (the start and the end) gets the speed at its other end: the controller
// starts and stops the program under its own acceleration limit.
struct ScheduledVertices {
  std::vector<ThetaRho> v;
  std::vector<double> speeds;  // m/s, one per segment
};

ScheduledVertices schedule_vertices(const std::vector<ThetaRho>& v, const SpeedProfile& prof, double tolerance) {
  constexpr int kSamples = 64;
  constexpr double kSpread = 1.05, kMargin = 1.011;
  auto at = [](const ThetaRho& a, const ThetaRho& b, double f) {
    return ThetaRho{a.theta + f * (b.theta - a.theta), a.rho + f * (b.rho - a.rho)};
  };
  auto xy = [](const ThetaRho& p) { return Vec2{p.rho * std::cos(p.theta), p.rho * std::sin(p.theta)}; };
  const size_t n = v.size() - 1;
  std::vector<double> cum(n * kSamples + 1, 0.0);  // spiral length at sample k of segment i: cum[i * kSamples + k]
  for (size_t i = 0; i < n; ++i)
    for (int k = 1; k <= kSamples; ++k) {
      const double f0 = static_cast<double>(k - 1) / kSamples, f1 = static_cast<double>(k) / kSamples;
      cum[i * kSamples + k] = cum[i * kSamples + k - 1] + norm(xy(at(v[i], v[i + 1], f1)) - xy(at(v[i], v[i + 1], f0)));
    }
  const double L = prof.length();
  const double scale = cum.back() > 0.0 ? L / cum.back() : 0.0;
  const std::vector<double> kinks = prof.kinks();
  // the smallest and largest speed of the schedule over [sa, sb] (V^2 is linear between the kinks)
  auto range = [&](double sa, double sb, double& lo, double& hi) {
    sa = std::clamp(sa, 0.0, L);
    sb = std::clamp(sb, 0.0, L);
    lo = std::min(prof.speed_at(sa), prof.speed_at(sb));
    hi = std::max(prof.speed_at(sa), prof.speed_at(sb));
    for (auto it = std::upper_bound(kinks.begin(), kinks.end(), sa); it != kinks.end() && *it < sb; ++it) {
      lo = std::min(lo, prof.speed_at(*it));
      hi = std::max(hi, prof.speed_at(*it));
    }
  };
  ScheduledVertices out;
  out.v.push_back(v.front());
  for (size_t i = 0; i < n; ++i) {
    int k0 = 0;
    while (k0 < kSamples) {
      const double sa = scale * cum[i * kSamples + k0];
      int k1 = k0 + 1;
      for (; k1 < kSamples; ++k1) {
        double lo, hi;
        range(sa, scale * cum[i * kSamples + k1 + 1], lo, hi);
        if (!(hi <= kSpread * lo)) break;
      }
      const double sb = scale * cum[i * kSamples + k1];
      double lo, hi;
      range(sa - tolerance, sb + tolerance, lo, hi);
      if (!(lo > 0.0)) range(sa, sb, lo, hi);
      if (!(lo > 0.0)) lo = std::max(prof.speed_at(std::clamp(sa, 0.0, L)), prof.speed_at(std::clamp(sb, 0.0, L)));
      out.v.push_back(k1 == kSamples ? v[i + 1] : at(v[i], v[i + 1], static_cast<double>(k1) / kSamples));
      out.speeds.push_back(lo / kMargin);
      k0 = k1;
    }
  }
  return out;
}

// The contours of a lifting job as theta-rho vertices within the tolerance, each on the arm's turn nearest the end
// of the one before (as the tape steps them: pipeline/job_tape).
std::vector<std::vector<ThetaRho>> lifting_strokes(const Job& job, double tolerance, std::vector<ToolPathPtr>& paths) {
  std::vector<std::vector<ThetaRho>> out;
  for (size_t k = 0; k < job.parts.size(); ++k) {
    paths.push_back(in_file(job.file, [&] { return make_tool_path(job.parts[k], job.placement, job.tool, job.motion.travel); }));
    std::vector<ThetaRho> v = in_file(job.file, [&] { return to_theta_rho(*paths.back(), tolerance); });
    if (!out.empty()) {
      const double turn = 2.0 * std::numbers::pi;
      const double shift = turn * std::nearbyint((out.back().back().theta - v.front().theta) / turn);
      for (ThetaRho& x : v) x.theta += shift;
    }
    out.push_back(std::move(v));
  }
  return out;
}

ExportResult export_lifting(const Job& job, const ExportOptions& o, std::ostream& out) {
  ExportResult r;
  if (o.format == ExportFormat::thr)
    throw InputError("a theta-rho file cannot lift the tool, and this machine lifts it between the drawing's " +
                         std::to_string(job.parts.size()) +
                         " contours: export G-code (--format gcode) or an SVG, or give a machine with tool_lift = false "
                         "to draw the connecting moves",
                     job.file);
  std::vector<ToolPathPtr> paths;
  const std::vector<std::vector<ThetaRho>> strokes = lifting_strokes(job, o.tolerance, paths);
  for (const ToolPathPtr& p : paths) r.path_length_m += arc_length(*p, p->u_begin(), p->u_end());
  if (o.format == ExportFormat::svg) {
    std::vector<SvgPolyline> lines;
    for (size_t k = 0; k < paths.size(); ++k) {
      if (k > 0) lines.push_back({sample_theta_rho({strokes[k - 1].back(), strokes[k].front()}, 0.25 * o.tolerance), false});
      lines.push_back({sample_curve(*paths[k], 0.25 * o.tolerance), true});
    }
    for (const SvgPolyline& l : lines) {
      for (Vec2 p : l.points) r.rho_max_m = std::max(r.rho_max_m, norm(p));
      r.points += l.points.size();
    }
    SvgOptions so;
    so.work_radius = job.machine.grid.r_max;
    so.work_radius_min = job.machine.grid.r_min;
    so.title = job.contour->name();
    write_svg_document(out, lines, so);
    return r;
  }
  for (const auto& v : strokes) {
    r.vertices += v.size();
    r.rho_max_m = std::max(r.rho_max_m, rho_max(v));
  }
  if (job.motion.time_optimal)
    throw InputError("G-code of a time-optimal schedule follows one contour: this machine lifts its tool between the "
                     "drawing's contours; give [motion] speed without speed_profile", job.file);
  const GcodeSpec spec = export_gcode_spec(job, o, r.rho_max_m);
  r.gcode = in_file(job.file, [&] { return write_gcode_lifting(out, strokes, spec, job.motion.speed, source_lines(job, o)); });
  return r;
}

}  // namespace

const char* to_string(ExportFormat f) {
  switch (f) {
    case ExportFormat::thr: return "thr";
    case ExportFormat::gcode: return "gcode";
    case ExportFormat::svg: return "svg";
  }
  return "?";
}

ExportResult export_job(const Job& job, const ExportOptions& o, const Progress& progress) {
  std::ostringstream out;
  ExportResult r = export_job(job, o, out, progress);
  r.content = std::move(out).str();
  return r;
}

void check_export_tolerance(double tolerance) {
  if (!(tolerance > 0.0) || !std::isfinite(tolerance)) throw InputError("must be a positive length", "--tolerance");
  if (tolerance < kMinExportTolerance)
    throw InputError("must be at least 0.0001 mm (" + significant(tolerance * 1e3, 3) +
                         " mm is far below what any machine follows)",
                     "--tolerance");
}

ExportResult export_job(const Job& job, const ExportOptions& o, std::ostream& out, const Progress& progress) {
  check_export_tolerance(o.tolerance);
  if (job_lifts_tool(job)) return export_lifting(job, o, out);
  report_progress(progress, 0.0);
  const ToolPathPtr path = make_job_path(job);
  ExportResult r;
  r.path_length_m = arc_length(*path, path->u_begin(), path->u_end());
  report_progress(progress, 0.2);
  if (o.format == ExportFormat::svg) {
    const std::vector<Vec2> pts = sample_curve(*path, 0.25 * o.tolerance);
    for (Vec2 p : pts) r.rho_max_m = std::max(r.rho_max_m, norm(p));
    SvgOptions so;
    so.work_radius = job.machine.grid.r_max;
    so.work_radius_min = job.machine.grid.r_min;
    so.title = job.contour->name();
    r.points = pts.size();
    report_progress(progress, 0.7);
    write_svg_document(out, {{pts, true}}, so);
    report_progress(progress, 1.0);
    return r;
  }
  // a theta-rho pattern drawn as it is (about the machine pole, forward, no tool offset) keeps its own vertices
  const ThetaRhoPath* pattern = as_theta_rho_path(*job.contour);
  const bool as_is = pattern && job.placement.C == 0.0 && job.tool.radius == 0.0 && !job.motion.travel.reverse &&
                     !job.motion.travel.start_parameter;
  // (a pattern's own vertices are not copied: a large pattern's export holds them once)
  std::vector<ThetaRho> fitted;
  if (!as_is) fitted = in_file(job.file, [&] { return to_theta_rho(*path, o.tolerance); });
  const std::vector<ThetaRho>& v = as_is ? pattern->vertices() : fitted;
  r.vertices = v.size();
  r.rho_max_m = rho_max(v);
  report_progress(progress, 0.6);
  if (o.format == ExportFormat::thr) {
    if (!job.machine.grid.r_max)
      throw InputError("a .thr file gives rho as a fraction of the table radius: the machine needs r_max", job.file);
    const double R = *job.machine.grid.r_max;
    check_reach(job, r.rho_max_m, R, "the machine's r_max");
    std::vector<ThetaRho> norm_v = v;
    for (ThetaRho& p : norm_v) p.rho = std::min(p.rho / R, 1.0);
    std::vector<std::string> head = source_lines(job, o);
    head.push_back("theta in radians, rho in 0..1 of r_max = " + mm(R));
    write_thr(out, norm_v, head);
  } else {
    const GcodeSpec spec = export_gcode_spec(job, o, r.rho_max_m);
    if (job.motion.time_optimal) {
      // each move's feed from the schedule: inverse time gives every move its own duration (export_gcode_spec)
      const SpeedProfilePtr prof = time_optimal_job_profile(job);
      const ScheduledVertices sv = schedule_vertices(v, *prof, o.tolerance);
      std::vector<std::string> head = source_lines(job, o);
      head.push_back("speed: time-optimal schedule, " + significant(prof->total_time(), 6) + " s, at most " +
                     significant(job.motion.speed * 1e3, 4) + " mm/s");
      r.gcode = in_file(job.file, [&] { return write_gcode(out, sv.v, spec, sv.speeds, head); });
    } else {
      r.gcode = in_file(job.file, [&] { return write_gcode(out, v, spec, job.motion.speed, source_lines(job, o)); });
    }
  }
  report_progress(progress, 1.0);
  return r;
}

}  // namespace polarcam
