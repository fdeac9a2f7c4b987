#include "job/pattern.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include <cmath>
#include <numbers>

#include "cam/dxf_import.hpp"
#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/image_trace.hpp"
#include "cam/input_file.hpp"
#include "cam/path.hpp"
#include "cam/point_files.hpp"
#include "cam/segments.hpp"
#include "cam/svg_import.hpp"
#include "cam/thr_export.hpp"
#include "cam/thr_file.hpp"
#include "job/job_contour.hpp"
#include "job/job_dynamics.hpp"
#include "job/job_optimize.hpp"
#include "job/toml_section.hpp"

namespace polarcam {

void check_pattern_travel(const std::vector<ThetaRho>& vertices, double dtheta, const std::string& where) {
  // the arm turns through at least the pattern's theta travel
  double travel = 0.0;
  for (size_t i = 1; i < vertices.size(); ++i) travel += std::abs(vertices[i].theta - vertices[i - 1].theta);
  const double steps = travel / dtheta;
  if (!(steps <= kMaxPatternSteps))
    throw InputError("the pattern turns the arm " + significant(travel / (2.0 * std::numbers::pi), 3) +
                         " times: at least " + significant(steps, 3) + " angular steps on this machine, more than the " +
                         significant(kMaxPatternSteps, 3) + " a tape may hold; is its theta in radians?",
                     where);
}

namespace {

using json = nlohmann::ordered_json;

// Several contours of a drawing as one theta-rho path, joined in order by the moves a sand table makes between
// them; one contour keeps its exact curve.
CurvePtr join_contours(const std::vector<CurvePtr>& curves, double tolerance, const std::string& path,
                       const std::string& name, const std::string& what, json& prov) {
  if (curves.size() == 1) return curves.front();
  // several contours: one theta-rho path, joined by the moves a sand table makes between them
  std::vector<ThetaRho> all;
  for (size_t i = 0; i < curves.size(); ++i) {
    std::vector<ThetaRho> v = in_file(path, [&] { return to_theta_rho(*curves[i], tolerance); });
    if (!all.empty()) {
      // the next contour on the arm's nearest turn: theta continues from where the last one ended
      const double shift = 2.0 * std::numbers::pi * std::nearbyint((all.back().theta - v.front().theta) / (2.0 * std::numbers::pi));
      for (ThetaRho& x : v) x.theta += shift;
      if (v.front().theta == all.back().theta && v.front().rho == all.back().rho) v.erase(v.begin());
    }
    all.insert(all.end(), v.begin(), v.end());
  }
  prov["tolerance_m"] = tolerance;
  prov["vertices"] = all.size();
  return in_file(path, [&] { return make_theta_rho_path(std::move(all), what + " " + name); });
}

// The contour of a pattern file, in the machine's frame (the pattern's origin is the machine pole).
CurvePtr pattern_contour(const std::string& path, const Machine& m, double tolerance, const TraceOptions& trace, json& prov,
                         std::string& kind, size_t& contours, std::vector<CurvePtr>& parts) {
  const std::string ext = lower_extension(path);
  const std::string name = std::filesystem::path(path).filename().string();
  if (ext == ".thr") {
    kind = "theta-rho";
    if (!m.grid.r_max)
      throw InputError("the machine has no r_max: a theta-rho pattern's rho = 1 is the table's radius r_max", "--machine");
    const ThrPattern pattern = read_thr(path);
    check_pattern_travel(pattern.vertices, m.grid.dtheta, path);
    return jobfile::theta_rho_contour(pattern, *m.grid.r_max, name, prov);
  }
  if (ext == ".csv") {
    kind = "points";
    std::vector<Vec2> pts = read_points_csv(path, 1e-3);
    const bool closed = pts.size() > 2 && pts.front() == pts.back();
    prov["kind"] = "points";
    prov["file"] = name;
    prov["unit_m"] = 1e-3;
    prov["interpolation"] = "line";
    prov["count"] = pts.size();
    prov["closed"] = closed;
    return in_file(path, [&] { return jobfile::polyline_contour(pts, closed); });
  }
  if (ext == ".dxf") {
    kind = "dxf";
    DxfOptions o;
    o.unit_m = 1e-3;
    DxfPath d = read_dxf_path(path, o);
    prov["kind"] = "dxf";
    prov["file"] = name;
    prov["unit_m"] = o.unit_m;
    prov["entities"] = d.entities;
    prov["closed"] = d.closed;
    const bool closed = d.closed;
    return in_file(path, [&] { return make_path(std::move(d.segments), closed); });
  }
  if (ext == ".svg") {
    kind = "svg";
    SvgDrawing d = read_svg(path);
    std::vector<CurvePtr> curves;
    for (const SvgContour& c : d.contours) curves.push_back(c.curve);
    // centred on the pole and, on a machine with a rim, scaled so that the drawing's box fits inside it
    const Box box = bounding_box(curves);
    const Vec2 centre = 0.5 * (box.lo + box.hi);
    const double half_diagonal = 0.5 * std::hypot(box.width(), box.height());
    double scale = 1.0;
    if (m.grid.r_max && half_diagonal > 0.0) scale = 0.98 * *m.grid.r_max / half_diagonal;
    for (CurvePtr& c : curves) c = transform_curve(c, scale, -scale * centre);
    prov["kind"] = "svg";
    prov["file"] = name;
    prov["contours"] = curves.size();
    prov["scale"] = scale;
    prov["centre_m"] = {centre.x, centre.y};
    contours = curves.size();
    // a machine that lifts its tool steps each contour as it is (pipeline/job_tape); the joined path is the job's
    // one path for the commands that take one
    if (curves.size() > 1 && m.tool_lift) parts = curves;
    return join_contours(curves, tolerance, path, name, "svg", prov);
  }
  if (is_image_file(path)) {
    kind = "image";
    const Tracing t = trace_image(read_image(path), trace, path);
    std::vector<CurvePtr> curves;
    for (const TracedContour& c : t.contours) curves.push_back(c.curve);
    // a template keeps its size: the image's centre on the pole
    const Vec2 centre{0.5 * t.width_m(), 0.5 * t.height_m()};
    for (CurvePtr& c : curves) c = transform_curve(c, 1.0, -1.0 * centre);
    prov["kind"] = "image";
    prov["file"] = name;
    prov["pixels"] = {t.width_px, t.height_px};
    prov["pixel_size_m"] = t.pixel_size_m;
    prov["threshold"] = trace.threshold;
    prov["invert"] = trace.invert;
    prov["despeckle_px"] = trace.despeckle;
    prov["contours"] = curves.size();
    contours = curves.size();
    if (curves.size() > 1 && m.tool_lift) parts = curves;
    return join_contours(curves, tolerance, path, name, "image", prov);
  }
  throw InputError("not a pattern file: give .thr, .svg, .dxf, .csv or an image (.png, .pbm, .pgm), or a job file", path);
}

Job pattern_job(const std::string& path, const PatternOptions& o) {
  if (o.machine_file.empty())
    throw InputError("a pattern file needs the machine that draws it: --machine FILE (e.g. examples/machines/sand-table.toml)", "--machine");
  if (o.speed_used && !o.speed)
    throw InputError("a pattern file needs the speed along it: --speed (e.g. \"40 mm/s\")", "--speed");
  const double speed = o.speed.value_or(kUnusedSpeed);
  if (!(speed > 0.0)) throw InputError("must be a positive speed", "--speed");
  Job job;
  job.file = path;
  json prov;
  prov["format"] = "polarcam-job/1";
  job.machine = load_machine(o.machine_file, &prov["machine"]);
  if (!(o.tolerance > 0.0)) throw InputError("must be a positive length", "--tolerance");
  job.contour = pattern_contour(path, job.machine, o.tolerance, o.trace, prov["contour"], job.contour_kind, job.contours,
                                job.parts);
  prov["placement"] = {{"C_m", 0.0}, {"beta_rad", 0.0}};
  job.tool.side = ToolSide::left;
  prov["tool"] = {{"radius_m", 0.0}, {"side", "left"}};
  job.motion.speed = speed;
  job.motion.rule = StepRule::nearest;
  // the provenance's keys in their order of old (the tapes' bytes are compared): the speed only when it was given
  if (o.speed)
    prov["motion"] = {{"speed_mps", *o.speed}, {"rule", "nearest"}, {"direction", "forward"}};
  else
    prov["motion"] = {{"rule", "nearest"}, {"direction", "forward"}};
  job.cartesian.resolution = job.machine.grid.dr;
  job.cartesian.tolerance = 0.25 * job.machine.grid.dr;
  // the optional tables of a job, absent: their defaults
  jobfile::Section none(nullptr, path, "optimize");
  job.optimize = jobfile::parse_optimize(none);
  job.load = jobfile::parse_load(jobfile::Section(nullptr, path, "load"));
  job.safety_factor = jobfile::parse_limits(jobfile::Section(nullptr, path, "limits"));
  job.provenance = std::move(prov);
  return job;
}

}  // namespace

bool is_pattern_file(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".thr" || ext == ".svg" || ext == ".dxf" || ext == ".csv" || is_image_file(path);
}

Job load_job_or_pattern(const std::string& path, const PatternOptions& o) {
  // a speed the command does not use, for a pattern or a job file alike
  if (!o.speed_used && o.speed)
    throw InputError("does not enter what this command computes (the path's geometry alone): leave it out", "--speed");
  if (is_pattern_file(path)) return pattern_job(path, o);
  if (!o.machine_file.empty())
    throw InputError("applies to pattern files (.thr, .svg, .dxf, .csv, images); a job file names its machine in [machine]", "--machine");
  Job job = load_job(path);
  if (o.speed) {
    if (!(*o.speed > 0.0)) throw InputError("must be a positive speed", "--speed");
    job.motion.speed = *o.speed;
    job.motion.table.clear();
    job.motion.accel.reset();
    job.motion.rollers.reset();
    job.motion.time_optimal = false;
    job.provenance.erase("template");
    job.provenance["motion"].erase("speed_profile");
    job.provenance["motion"].erase("accel_mps2");
    job.provenance["motion"]["speed_mps"] = *o.speed;
  }
  return job;
}

}  // namespace polarcam
