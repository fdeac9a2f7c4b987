#include "cam/svg_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <ostream>
#include <sstream>

#include "cam/error.hpp"
#include "cam/format.hpp"

namespace polarcam {
namespace {

constexpr int kStartPieces = 16;   // a piece starts as up to this many chords,
constexpr int kStartBudget = 4096; // and the whole curve as about this many (a polyline of 10^5 pieces: one each)
constexpr int kChecks = 15;        // interior points checked against each chord
constexpr int kMaxRefine = 30;

double dist_to_chord(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double L2 = dot(d, d);
  const double t = L2 > 0.0 ? std::clamp(dot(p - a, d) / L2, 0.0, 1.0) : 0.0;
  return norm(p - (a + t * d));
}

void refine(const Curve& c, double ua, Vec2 pa, double ub, Vec2 pb, double tol, int depth, std::vector<Vec2>& out) {
  bool ok = true;
  if (depth < kMaxRefine) {
    const Vec2 ta = c.eval(ua, 1).d1, tb = c.eval(ub, 1).d1;
    // more than a sixteenth of a turn between the ends' tangents: split (a loop may return near its start)
    if (norm(ta) > 0.0 && norm(tb) > 0.0 && dot(ta, tb) < std::cos(std::numbers::pi / 8) * norm(ta) * norm(tb)) ok = false;
    for (int k = 1; ok && k <= kChecks; ++k) {
      const Vec2 p = c.eval(ua + (ub - ua) * k / (kChecks + 1), 0).p;
      if (!(dist_to_chord(p, pa, pb) <= tol)) ok = false;
    }
  }
  if (ok) {
    if (!std::isfinite(pb.x) || !std::isfinite(pb.y)) throw InputError("the path has a point that is not finite");
    out.push_back(pb);
    return;
  }
  const double um = 0.5 * (ua + ub);
  const Vec2 pm = c.eval(um, 0).p;
  refine(c, ua, pa, um, pm, tol, depth + 1, out);
  refine(c, um, pm, ub, pb, tol, depth + 1, out);
}

// "12.3450" in mm from metres, fixed decimals, never "-0.0000".
std::string mm_fixed(double m) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4f", m * 1e3);
  std::string s(buf);
  if (s.find_first_not_of("-0.") == std::string::npos && s[0] == '-') s.erase(0, 1);
  return s;
}

void polyline(std::ostream& s, const std::vector<Vec2>& pts) {
  s << "    <polyline points=\"";
  for (size_t i = 0; i < pts.size(); ++i) {
    if (i > 0) s << ((i % 8 == 0) ? "\n      " : " ");
    s << mm_fixed(pts[i].x) << ',' << mm_fixed(pts[i].y);
  }
  s << "\"/>\n";
}

}  // namespace

std::vector<Vec2> sample_curve(const Curve& c, double chord_tol) {
  if (!(chord_tol > 0.0) || !std::isfinite(chord_tol)) throw InputError("the chord tolerance must be a positive length");
  std::vector<double> cuts{c.u_begin()};
  for (double b : c.breakpoints())
    if (b > cuts.back()) cuts.push_back(b);
  if (c.u_end() > cuts.back()) cuts.push_back(c.u_end());
  std::vector<Vec2> out{c.eval(c.u_begin(), 0).p};
  const size_t pieces = cuts.size() - 1;
  const int start = static_cast<int>(std::clamp<size_t>(kStartBudget / std::max<size_t>(pieces, 1), 1, kStartPieces));
  for (size_t i = 0; i + 1 < cuts.size(); ++i)
    for (int k = 0; k < start; ++k) {
      const double ua = cuts[i] + (cuts[i + 1] - cuts[i]) * k / start;
      const double ub = k + 1 == start ? cuts[i + 1] : cuts[i] + (cuts[i + 1] - cuts[i]) * (k + 1) / start;
      refine(c, ua, out.back(), ub, c.eval(ub, 0).p, chord_tol, 0, out);
    }
  return out;
}

std::vector<Vec2> sample_theta_rho(const std::vector<ThetaRho>& v, double chord_tol) {
  const CurvePtr path = make_theta_rho_path(v, "theta-rho");
  return sample_curve(*path, chord_tol);
}

std::string svg_document(const std::vector<SvgPolyline>& lines, const SvgOptions& o) {
  std::ostringstream s;
  write_svg_document(s, lines, o);
  return std::move(s).str();
}

void write_svg_document(std::ostream& s, const std::vector<SvgPolyline>& lines, const SvgOptions& o) {
  // extent in metres
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;  // the pole is always shown
  for (const SvgPolyline& l : lines)
    for (Vec2 p : l.points) {
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
      y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    }
  if (o.work_radius) {
    const double R = *o.work_radius;
    x0 = std::min(x0, -R), x1 = std::max(x1, R), y0 = std::min(y0, -R), y1 = std::max(y1, R);
  }
  x0 -= o.margin, x1 += o.margin, y0 -= o.margin, y1 += o.margin;
  const double size = std::max(x1 - x0, y1 - y0);
  const double stroke = std::max(size * 1.5e-3, 1e-5);  // m
  s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  // y up: the content is drawn in a group flipped about the x axis, so the viewBox spans -y1 .. -y0
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + mm_fixed(x1 - x0) + "mm\" height=\"" + mm_fixed(y1 - y0) +
       "mm\" viewBox=\"" + mm_fixed(x0) + " " + mm_fixed(-y1) + " " + mm_fixed(x1 - x0) + " " + mm_fixed(y1 - y0) + "\">\n";
  if (!o.title.empty()) s << "  <title>" + xml_escape(o.title) + "</title>\n";
  s << "  <g transform=\"scale(1,-1)\" fill=\"none\" stroke-linecap=\"round\" stroke-linejoin=\"round\">\n";
  s << "  <g id=\"work-area\" stroke=\"#9e9e9e\" stroke-width=\"" + mm_fixed(stroke) + "\">\n";
  if (o.work_radius) s << "    <circle cx=\"0\" cy=\"0\" r=\"" + mm_fixed(*o.work_radius) + "\"/>\n";
  if (o.work_radius_min > 0.0) s << "    <circle cx=\"0\" cy=\"0\" r=\"" + mm_fixed(o.work_radius_min) + "\"/>\n";
  const std::string c = mm_fixed(4 * stroke), mc = mm_fixed(-4 * stroke);
  s << "    <path d=\"M " + mc + ",0 H " + c + " M 0," + mc + " V " + c + "\"/>\n";
  s << "  </g>\n";
  s << "  <g id=\"connecting\" stroke=\"#e65100\" stroke-width=\"" + mm_fixed(stroke) + "\" stroke-dasharray=\"" +
       mm_fixed(4 * stroke) + " " + mm_fixed(3 * stroke) + "\">\n";
  for (const SvgPolyline& l : lines)
    if (!l.drawn && l.points.size() >= 2) polyline(s, l.points);
  s << "  </g>\n";
  s << "  <g id=\"path\" stroke=\"#0d47a1\" stroke-width=\"" + mm_fixed(2 * stroke) + "\">\n";
  const SvgPolyline* first = nullptr;
  const SvgPolyline* last = nullptr;
  for (const SvgPolyline& l : lines)
    if (l.drawn && l.points.size() >= 2) {
      polyline(s, l.points);
      if (!first) first = &l;
      last = &l;
    }
  s << "  </g>\n";
  s << "  <g id=\"markers\" stroke=\"none\">\n";
  if (first) {
    const Vec2 a = first->points.front(), b = last->points.back();
    s << "    <circle id=\"start\" fill=\"#2e7d32\" cx=\"" + mm_fixed(a.x) + "\" cy=\"" + mm_fixed(a.y) + "\" r=\"" + mm_fixed(4 * stroke) + "\"/>\n";
    s << "    <rect id=\"end\" fill=\"#c62828\" x=\"" + mm_fixed(b.x - 3 * stroke) + "\" y=\"" + mm_fixed(b.y - 3 * stroke) +
         "\" width=\"" + mm_fixed(6 * stroke) + "\" height=\"" + mm_fixed(6 * stroke) + "\"/>\n";
  }
  s << "  </g>\n";
  s << "  </g>\n";
  s << "</svg>\n";
}

}  // namespace polarcam
