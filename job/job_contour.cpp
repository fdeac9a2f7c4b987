#include "job/job_contour.hpp"

#include <zlib.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/dxf_import.hpp"
#include "cam/error.hpp"
#include "cam/expr_curves.hpp"
#include "cam/input_file.hpp"
#include "cam/path.hpp"
#include "cam/point_files.hpp"
#include "cam/spline.hpp"
#include "cam/thr_file.hpp"

namespace polarcam::jobfile {
namespace {

// An angle of a contour (an arc's sweep, the parameter range of a spiral or a polar expression) beyond this is a
// wrong unit or a damaged number: no contour turns some 16 000 times, and its track would need a piece for every
// radian or so (it was refused much later, as a path passing too close to the pole).
constexpr double kMaxContourAngle = 1e5;
void refuse_too_many_turns(const Section& s, const char* key, double angle) {
  if (!(std::abs(angle) <= kMaxContourAngle))
    s.fail(key, "is beyond 1e5 rad (about 15 900 turns): no contour turns that often; check the number and its unit "
                "(rad, deg)");
}

constexpr double kTwoPi = 2.0 * std::numbers::pi;

ExprConstants read_constants(Section& s, nlohmann::ordered_json& prov) {
  ExprConstants c;
  Section cs = s.subsection("constants");
  if (!cs.present()) return c;
  const toml::node* n = s.node("constants");
  for (const auto& [k, v] : *n->as_table()) {
    std::string key(k.str());
    auto val = cs.number(key);
    c[key] = *val;
    prov["constants"][key] = *val;
  }
  cs.finish();
  return c;
}

double unit_of(Section& s) {
  auto u = s.string("unit");
  if (!u) s.fail_section("expression and point-list contours need 'unit', the length unit of their numbers (e.g. \"cm\")");
  try {
    return parse_quantity_as("1 " + *u, dim::length);
  } catch (const InputError& e) {
    s.fail("unit", e.what());
  }
}

bool closed_auto(const Curve& c) {
  Vec2 a = c.eval(c.u_begin(), 0).p, b = c.eval(c.u_end(), 0).p;
  double scale = std::max({norm(a), norm(b), 1e-3});
  return norm(a - b) <= 1e-9 * scale;
}

std::string resolve(const std::string& base, const std::string& f) {
  std::filesystem::path p(f);
  if (p.is_relative()) p = std::filesystem::path(base) / p;
  return p.lexically_normal().string();
}

uint32_t points_crc(const std::vector<Vec2>& pts) {
  uint32_t c = static_cast<uint32_t>(crc32(0L, Z_NULL, 0));
  for (const Vec2& p : pts) {
    double xy[2] = {p.x, p.y};
    c = static_cast<uint32_t>(crc32(c, reinterpret_cast<const Bytef*>(xy), sizeof xy));
  }
  return c;
}

bool is_thr(const std::string& file) { return lower_extension(file) == ".thr"; }

// [contour] kind = "theta-rho" (or a points contour whose file is a .thr): the pattern's own segments, linear in
// theta and rho.
CurvePtr parse_theta_rho(Section& s, const std::string& base_dir, nlohmann::ordered_json& prov,
                         std::optional<double> table_radius) {
  const std::string file = s.require_string("file");
  double scale = 0.0;
  if (s.has("rho_scale")) {
    scale = s.require_quantity("rho_scale", dim::length);
    if (!(scale > 0.0)) s.fail("rho_scale", "must be a positive length");
  } else if (table_radius) {
    scale = *table_radius;
  } else {
    s.fail_section("a theta-rho pattern needs 'rho_scale' (the radius rho = 1 means) or a machine with r_max");
  }
  const ThrPattern p = read_thr(resolve(base_dir, file));
  return theta_rho_contour(p, scale, std::filesystem::path(file).filename().string(), prov);
}

CurvePtr parse_points(Section& s, const std::string& base_dir, nlohmann::ordered_json& prov,
                      std::optional<double> table_radius) {
  std::vector<Vec2> pts;
  std::string source;
  const toml::node* inline_pts = s.node("points");
  auto file = s.string("file");
  if ((inline_pts != nullptr) == file.has_value()) s.fail_section("give either 'points' (a list) or 'file' (CSV or .thr)");
  if (file && is_thr(*file)) {
    if (s.has("interpolation")) s.fail("interpolation", "does not apply to a .thr file: its points are joined by segments linear in theta and rho");
    return parse_theta_rho(s, base_dir, prov, table_radius);
  }
  const std::string interp = s.string("interpolation").value_or("spline");
  if (interp != "spline" && interp != "line") s.fail("interpolation", "must be \"spline\" or \"line\"");
  if (file) {
    std::string path = resolve(base_dir, *file);
    source = std::filesystem::path(*file).filename().string();
    pts = read_points_csv(path, unit_of(s));
  } else {
    const toml::array* arr = inline_pts->as_array();
    if (!arr) s.fail("points", "expected a list of points [[x, y], ...]");
    std::optional<double> unit;
    if (s.has("unit")) unit = unit_of(s);
    for (size_t i = 0; i < arr->size(); ++i) {
      const toml::array* pr = arr->get(i)->as_array();
      if (!pr || pr->size() != 2) s.fail("points", "entry " + std::to_string(i + 1) + " is not a pair [x, y]");
      double xy[2];
      for (size_t k = 0; k < 2; ++k) {
        const toml::node& n = *pr->get(k);
        if (auto str = n.value<std::string>()) {
          try {
            xy[k] = parse_quantity_as(*str, dim::length);
          } catch (const InputError& e) {
            s.fail("points", "entry " + std::to_string(i + 1) + ": " + e.what());
          }
        } else if (n.is_number()) {
          if (!unit) s.fail("points", "plain numbers need 'unit' (e.g. unit = \"mm\")");
          xy[k] = *n.value<double>() * *unit;
        } else {
          s.fail("points", "entry " + std::to_string(i + 1) + " is not a pair of numbers");
        }
      }
      pts.push_back({xy[0], xy[1]});
    }
  }
  bool closed = s.boolean("closed").value_or(pts.size() > 2 && norm(pts.front() - pts.back()) == 0.0);
  prov["count"] = pts.size();
  prov["closed"] = closed;
  prov["points_crc32"] = points_crc(pts);
  if (interp == "line") {
    prov["interpolation"] = "line";
    return polyline_contour(pts, closed);
  }
  return make_spline(pts, closed, source);
}

CurvePtr parse_path(Section& s, nlohmann::ordered_json& prov) {
  Vec2 cur = s.require_point("start");
  const Vec2 start = cur;
  const toml::node* segn = s.node("segments");
  if (!segn || !segn->is_array_of_tables()) s.fail_section("a path needs [[contour.segments]] entries");
  std::vector<PathSegment> segs;
  size_t i = 0;
  for (const auto& item : *segn->as_array()) {
    ++i;
    Section ss(item.as_table(), s.file(), s.name() + ".segments[" + std::to_string(i) + "]");
    std::string kind = ss.require_string("kind");
    nlohmann::ordered_json pj;
    pj["kind"] = kind;
    if (kind == "line") {
      Vec2 to = ss.require_point("to");
      PathSegment seg;
      seg.from = cur;
      seg.to = to;
      segs.push_back(seg);
    } else if (kind == "arc") {
      Vec2 c = ss.require_point("center");
      auto sweep = ss.quantity("sweep", dim::angle);
      auto to = ss.point("to");
      if (sweep.has_value() == to.has_value()) ss.fail_section("an arc needs either 'to' (with 'direction') or 'sweep'");
      if (sweep) refuse_too_many_turns(ss, "sweep", *sweep);
      try {
        if (sweep) {
          if (ss.has("direction")) ss.fail("direction", "is implied by the sign of 'sweep'");
          segs.push_back(make_arc_segment(cur, c, *sweep));
        } else {
          std::string dir = ss.string("direction").value_or("ccw");
          if (dir != "ccw" && dir != "cw") ss.fail("direction", "must be \"ccw\" or \"cw\"");
          segs.push_back(make_arc_segment_to(cur, *to, c, dir == "ccw"));
        }
      } catch (const InputError& e) {
        ss.fail_section(e.what());
      }
      pj["center_m"] = {c.x, c.y};
      pj["sweep_rad"] = segs.back().sweep;
    } else {
      ss.fail("kind", "unknown segment kind '" + kind + "' (line or arc)");
    }
    ss.finish();
    cur = segs.back().to;
    pj["to_m"] = {cur.x, cur.y};
    prov["segments"].push_back(pj);
  }
  bool closed = s.boolean("closed").value_or(norm(cur - start) <= 1e-9 * std::max(1.0, norm(start)));
  if (closed) segs.back().to = start;
  prov["start_m"] = {start.x, start.y};
  prov["closed"] = closed;
  try {
    return make_path(std::move(segs), closed);
  } catch (const InputError& e) {
    s.fail_section(e.what());
  }
}

CurvePtr parse_dxf(Section& s, const std::string& base_dir, nlohmann::ordered_json& prov) {
  std::string file = s.require_string("file");
  DxfOptions o;
  o.unit_m = unit_of(s);
  if (auto layer = s.string("layer")) {
    o.layer = *layer;
    prov["layer"] = *layer;
  }
  if (auto tol = s.quantity("join_tolerance", dim::length)) {
    if (!(*tol > 0)) s.fail("join_tolerance", "must be a positive length");
    o.join_tolerance = *tol / o.unit_m;
  }
  DxfPath d = read_dxf_path(resolve(base_dir, file), o);
  auto closed = s.boolean("closed");
  if (closed && *closed && !d.closed) s.fail("closed", "the drawing's chain does not end where it starts");
  bool is_closed = closed.value_or(d.closed);
  prov["unit_m"] = o.unit_m;
  prov["entities"] = d.entities;
  prov["closed"] = is_closed;
  std::vector<Vec2> ends;
  for (const auto& seg : d.segments) {
    ends.push_back(seg.to);
    if (seg.kind == PathSegment::Kind::arc) ends.push_back(seg.center);
  }
  prov["segments_crc32"] = points_crc(ends);
  return make_path(std::move(d.segments), is_closed);
}

}  // namespace

CurvePtr polyline_contour(const std::vector<Vec2>& pts, bool closed) {
  std::vector<PathSegment> segs;
  for (size_t i = 1; i < pts.size(); ++i) {
    if (pts[i] == (segs.empty() ? pts[0] : segs.back().to)) continue;  // repeated points are merged
    PathSegment seg;
    seg.from = segs.empty() ? pts[0] : segs.back().to;
    seg.to = pts[i];
    segs.push_back(seg);
  }
  if (segs.empty()) throw InputError("a polyline needs two distinct points");
  if (closed && !(segs.back().to == pts[0])) {
    PathSegment seg;
    seg.from = segs.back().to;
    seg.to = pts[0];
    segs.push_back(seg);
  }
  return make_path(std::move(segs), closed);
}

CurvePtr theta_rho_contour(const ThrPattern& p, double rho_scale, const std::string& source,
                           nlohmann::ordered_json& prov) {
  std::vector<ThetaRho> v = p.vertices;
  for (ThetaRho& x : v) x.rho *= rho_scale;
  // merging in normalised units first, then scaling, cannot make two neighbours equal: scaling is monotone
  uint32_t c = static_cast<uint32_t>(crc32(0L, Z_NULL, 0));
  for (const ThetaRho& x : p.vertices) {
    double tr[2] = {x.theta, x.rho};
    c = static_cast<uint32_t>(crc32(c, reinterpret_cast<const Bytef*>(tr), sizeof tr));
  }
  prov["kind"] = "theta-rho";
  prov["file"] = source;
  prov["rho_scale_m"] = rho_scale;
  prov["count"] = v.size();
  prov["merged"] = p.merged;
  prov["vertices_crc32"] = c;
  CurvePtr curve = make_theta_rho_path(std::move(v), "theta-rho " + source);
  prov["closed"] = curve->closed();
  return curve;
}

CurvePtr parse_contour(Section& s, const std::string& base_dir, nlohmann::ordered_json& prov, std::string& kind,
                       std::optional<double> table_radius) {
  if (!s.present()) throw InputError("the [contour] section is missing", s.file());
  kind = s.require_string("kind");
  prov["kind"] = kind;
  auto L = [&](const char* key) {
    double v = s.require_quantity(key, dim::length);
    prov[std::string(key) + "_m"] = v;
    return v;
  };
  auto Lopt = [&](const char* key, double def) {
    double v = s.quantity(key, dim::length, def);
    prov[std::string(key) + "_m"] = v;
    return v;
  };
  auto A = [&](const char* key, double def) {
    double v = s.quantity(key, dim::angle, def);
    prov[std::string(key) + "_rad"] = v;
    return v;
  };
  CurvePtr c;
  try {
    if (kind == "circle") {
      double r = L("radius");
      double cx = Lopt("center_x", 0.0), cy = Lopt("center_y", 0.0);
      c = make_circle({cx, cy}, r);
    } else if (kind == "line") {
      Vec2 a = s.require_point("from"), b = s.require_point("to");
      prov["from_m"] = {a.x, a.y};
      prov["to_m"] = {b.x, b.y};
      c = make_line(a, b);
    } else if (kind == "witch") {
      double a = L("a"), x0 = L("x_from"), x1 = L("x_to");
      c = make_witch(a, x0, x1);
    } else if (kind == "serpentine") {
      double a = L("a"), b = L("b"), x0 = L("x_from"), x1 = L("x_to");
      c = make_serpentine(a, b, x0, x1);
    } else if (kind == "limacon") {
      double a = L("a"), b = L("b");
      c = make_limacon(a, b);
    } else if (kind == "spiral") {
      double a = Lopt("a", 0.0);
      auto b = s.quantity("b", dim::length);
      auto pitch = s.quantity("pitch", dim::length);
      if (b.has_value() == pitch.has_value()) s.fail_section("a spiral needs either 'b' (growth per radian) or 'pitch' (per turn)");
      double bb = b ? *b : *pitch / kTwoPi;
      prov["b_m_per_rad"] = bb;
      double t0 = A("t_from", 0.0);
      double t1 = s.require_quantity("t_to", dim::angle);
      prov["t_to_rad"] = t1;
      refuse_too_many_turns(s, "t_from", t0);
      refuse_too_many_turns(s, "t_to", t1);
      c = make_spiral(a, bb, t0, t1);
    } else if (kind == "rose") {
      double a = L("a");
      int p = 0, q = 1;
      const toml::node* kn = s.node("k");
      if (!kn) s.fail_section("a rose needs 'k': a whole number (k = 3) or a ratio (k = \"2/3\")");
      if (kn->is_integer()) {
        p = static_cast<int>(*kn->value<int64_t>());
      } else if (auto ks = kn->value<std::string>()) {
        char extra = 0;
        if (std::sscanf(ks->c_str(), "%d/%d%c", &p, &q, &extra) != 2) s.fail("k", "expected a ratio such as \"2/3\"");
      } else {
        s.fail("k", "expected a whole number or a ratio such as \"2/3\"");
      }
      if (p <= 0 || q <= 0 || p > 1000000 || q > 1000000)
        s.fail("k", "must be a positive ratio of whole numbers, each at most 1000000");
      prov["k_den"] = q;
      prov["k"] = p;
      c = make_rose(a, p, q);
    } else if (kind == "polar") {
      std::string r = s.require_string("r");
      double unit = unit_of(s);
      double t0 = A("t_from", 0.0), t1 = s.quantity("t_to", dim::angle, kTwoPi);
      refuse_too_many_turns(s, "t_from", t0);
      refuse_too_many_turns(s, "t_to", t1);
      prov["t_to_rad"] = t1;
      prov["r"] = r;
      prov["unit_m"] = unit;
      ExprConstants k = read_constants(s, prov);
      auto closed = s.boolean("closed");
      c = make_polar_expr(r, t0, t1, closed.value_or(false), unit, k);
      if (!closed && closed_auto(*c)) c = make_polar_expr(r, t0, t1, true, unit, k);
    } else if (kind == "cartesian") {
      std::string y = s.require_string("y");
      double unit = unit_of(s);
      double x0 = L("x_from"), x1 = L("x_to");
      prov["y"] = y;
      prov["unit_m"] = unit;
      ExprConstants k = read_constants(s, prov);
      c = make_cartesian_expr(y, x0, x1, unit, k);
    } else if (kind == "parametric") {
      std::string x = s.require_string("x"), y = s.require_string("y");
      double unit = unit_of(s);
      auto t0 = s.number("t_from"), t1 = s.number("t_to");
      if (!t0 || !t1) s.fail_section("a parametric contour needs 't_from' and 't_to' (plain numbers)");
      prov["x"] = x;
      prov["y"] = y;
      prov["unit_m"] = unit;
      prov["t_from"] = *t0;
      prov["t_to"] = *t1;
      ExprConstants k = read_constants(s, prov);
      auto closed = s.boolean("closed");
      c = make_parametric_expr(x, y, *t0, *t1, closed.value_or(false), unit, k);
      if (!closed && closed_auto(*c)) c = make_parametric_expr(x, y, *t0, *t1, true, unit, k);
    } else if (kind == "points") {
      c = parse_points(s, base_dir, prov, table_radius);
    } else if (kind == "theta-rho") {
      c = parse_theta_rho(s, base_dir, prov, table_radius);
    } else if (kind == "dxf") {
      c = parse_dxf(s, base_dir, prov);
    } else if (kind == "path") {
      c = parse_path(s, prov);
    } else {
      s.fail("kind", "unknown contour kind '" + kind +
                         "' (circle, line, limacon, witch, serpentine, spiral, rose, polar, cartesian, parametric, points, theta-rho, path, dxf)");
    }
    // an expression can stand still: r = 0, or x and y that do not depend on the parameter (y(x) cannot)
    if ((kind == "polar" || kind == "parametric") && !(arc_length(*c, c->u_begin(), c->u_end()) > 0.0))
      s.fail_section("the contour has no length: every point of it is the same point (check its expressions and range)");
  } catch (const InputError& e) {
    if (e.names(s.file())) throw;
    // an expression's error is placed at its key (r, x, y): the message names the key and its line
    const bool expression = kind == "polar" || kind == "cartesian" || kind == "parametric";
    if (expression && !e.place().empty() && s.has(e.place())) s.fail(e.place(), e.message());
    s.fail_section(e.what());
  }
  s.finish();
  return c;
}

}  // namespace polarcam::jobfile
