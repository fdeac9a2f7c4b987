#include "report/report_figures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "report/report_numbers.hpp"

namespace polarcam::cli {
namespace {

// The corner of a panel (a box of 45 % of its width and half its height) that covers the fewest drawn points,
// where its legend hides least: the path and the work area count once per point, a marker (a pole) as much as a
// whole line.
// When even that corner covers something, the panel's extent grows on that side to make room.
plot::Panel::Legend emptiest_corner(plot::Panel& p) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const plot::Series& s : p.series)
    for (size_t i = 0; i < s.x.size(); ++i)
      x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]), y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
  using L = plot::Panel::Legend;
  const L corners[] = {L::top_right, L::top_left, L::bottom_right, L::bottom_left};
  L best = L::top_right;
  double best_n = 1e300;
  for (L c : corners) {
    const bool right = c == L::top_right || c == L::bottom_right, top = c == L::top_right || c == L::top_left;
    const double cx0 = right ? x1 - 0.45 * (x1 - x0) : x0, cx1 = right ? x1 : x0 + 0.45 * (x1 - x0);
    const double cy0 = top ? y1 - 0.5 * (y1 - y0) : y0, cy1 = top ? y1 : y0 + 0.5 * (y1 - y0);
    double n = 0.0;
    for (const plot::Series& s : p.series) {
      const double weight = s.x.size() == 1 ? 1000.0 : 1.0;
      for (size_t i = 0; i < s.x.size(); ++i)
        if (s.x[i] >= cx0 && s.x[i] <= cx1 && s.y[i] >= cy0 && s.y[i] <= cy1) n += weight;
    }
    if (n < best_n) best_n = n, best = c;
  }
  if (best_n > 0.0 && y1 > y0 && x1 > x0) {
    const double m = 0.05 * (y1 - y0);  // the default margin of plot.cpp
    p.xmin = x0 - 0.05 * (x1 - x0), p.xmax = x1 + 0.05 * (x1 - x0);
    if (best == L::top_right || best == L::top_left)
      p.ymin = y0 - m, p.ymax = y1 + 0.85 * (y1 - y0);
    else
      p.ymin = y0 - 0.85 * (y1 - y0), p.ymax = y1 + m;
  }
  return best;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using report_numbers::g;

void arc(plot::Series& s, double r, double a0, double a1, int n) {
  for (int i = 0; i <= n; ++i) {
    const double a = a0 + (a1 - a0) * i / n;
    s.x.push_back(r * std::cos(a));
    s.y.push_back(r * std::sin(a));
  }
}

}  // namespace

plot::Figure workarea_figure(const Job& job, const Curve& path, const Staircase& st, Vec2 c, double half) {
  plot::Figure f = plot::figure(1200, 600);
  f.cols = 2;
  const Grid& gr = job.machine.grid;
  // left: the whole work area, in mm
  plot::Panel a = plot::panel("The contour on the machine's work area", "x from the machine pole (mm)", "y (mm)", true);
  const double t0 = gr.theta_min.value_or(0.0), t1 = gr.theta_max.value_or(2.0 * std::numbers::pi);
  if (gr.r_max) {
    plot::Series w;
    w.label = "work area";
    w.color = plot::palette(6);
    w.width = 1.2;
    const double r0 = gr.r_min * 1e3, r1 = *gr.r_max * 1e3;
    arc(w, r1, t0, t1, 200);
    if (gr.theta_min) {
      w.x.push_back(r0 * std::cos(t1));
      w.y.push_back(r0 * std::sin(t1));
    }
    if (r0 > 0.0) arc(w, r0, t1, t0, 100);
    if (gr.theta_min) {
      w.x.push_back(r1 * std::cos(t0));
      w.y.push_back(r1 * std::sin(t0));
    }
    a.series.push_back(w);
  }
  plot::Series p;
  p.label = "tool path";
  p.color = plot::palette(0);
  p.width = 2.0;
  const int n = 3000;
  for (int i = 0; i <= n; ++i) {
    const Vec2 q = path.eval(path.u_begin() + (path.u_end() - path.u_begin()) * i / n, 0).p;
    p.x.push_back(q.x * 1e3);
    p.y.push_back(q.y * 1e3);
  }
  a.series.push_back(p);
  a.series.push_back(plot::marker(0.0, 0.0, "machine pole", 6, 2, 2.5));
  const Vec2 o1 = -1.0 * job.placement.pole();
  a.series.push_back(plot::marker(o1.x * 1e3, o1.y * 1e3, "contour pole", 1, 4, 1.6));
  a.series.push_back(plot::marker(c.x * 1e3, c.y * 1e3, "magnified (right)", 3, 4, 3.0));
  a.legend = emptiest_corner(a);
  f.panels.push_back(a);

  // right: the window, relative to its centre, in mm
  plot::Panel b = plot::panel(fmt::format("Staircase magnified around ({}, {}) mm", g(c.x * 1e3, 5), g(c.y * 1e3, 5)),
                              "x - x0 (mm)",
                              "y - y0 (mm)",
                              true);
  const double h = half * 1.0;
  auto inside = [&](Vec2 q) { return std::abs(q.x - c.x) <= 1.2 * h && std::abs(q.y - c.y) <= 1.2 * h; };
  // the staircase: radial steps straight, angular steps arcs about the pole
  std::vector<plot::Series> runs;
  plot::Series cur;
  auto flush = [&] {
    if (cur.x.size() >= 2 && runs.size() < 12) runs.push_back(cur);
    cur.x.clear();
    cur.y.clear();
  };
  int64_t nn = st.n0, mm = st.m0;
  auto node = [&](int64_t ni, double m) {
    const double r = static_cast<double>(ni) * gr.dr, th = m * gr.dtheta;
    return Vec2{r * std::cos(th), r * std::sin(th)};
  };
  for (uint8_t s : st.steps) {
    const int axis = s & 1, dir = (s & 2) ? 1 : -1;
    const int64_t n1 = axis == 0 ? nn + dir : nn, m1 = axis == 1 ? mm + dir : mm;
    const Vec2 a0 = node(nn, static_cast<double>(mm)), a1 = node(n1, static_cast<double>(m1));
    if (inside(a0) || inside(a1)) {
      if (cur.x.empty()) {
        cur.x.push_back((a0.x - c.x) * 1e3);
        cur.y.push_back((a0.y - c.y) * 1e3);
      }
      const int k = axis == 1 ? 6 : 1;
      for (int i = 1; i <= k; ++i) {
        const Vec2 q = axis == 1 ? node(nn, static_cast<double>(mm) + dir * static_cast<double>(i) / k) : a1;
        cur.x.push_back((q.x - c.x) * 1e3);
        cur.y.push_back((q.y - c.y) * 1e3);
      }
    } else {
      flush();
    }
    nn = n1;
    mm = m1;
  }
  flush();
  // the path through the window
  plot::Series pw;
  std::vector<plot::Series> pruns;
  const int np = 40000;
  for (int i = 0; i <= np; ++i) {
    const Vec2 q = path.eval(path.u_begin() + (path.u_end() - path.u_begin()) * i / np, 0).p;
    if (inside(q)) {
      pw.x.push_back((q.x - c.x) * 1e3);
      pw.y.push_back((q.y - c.y) * 1e3);
    } else if (!pw.x.empty()) {
      pruns.push_back(pw);
      pw.x.clear();
      pw.y.clear();
    }
  }
  if (!pw.x.empty()) pruns.push_back(pw);
  for (size_t i = 0; i < pruns.size(); ++i) {
    pruns[i].label = i == 0 ? "tool path" : "";
    pruns[i].color = plot::palette(0);
    pruns[i].width = 2.0;
    b.series.push_back(pruns[i]);
  }
  for (size_t i = 0; i < runs.size(); ++i) {
    runs[i].label = i == 0 ? "machine's staircase" : "";
    runs[i].color = plot::palette(1);
    runs[i].width = 1.6;
    b.series.push_back(runs[i]);
  }
  b.xmin = -h * 1e3;
  b.xmax = h * 1e3;
  b.ymin = -h * 1e3;
  b.ymax = h * 1e3;
  f.panels.push_back(b);
  return f;
}

plot::Figure schedules_figure(const Job& job, const ScheduleStudy& ss, double limit, std::optional<double> job_speed) {
  plot::Figure f = plot::figure(1100, 1150);
  f.rows = 3;
  const TorqueAnalysis& opt = ss.plan.schedule.check;
  const TorqueAnalysis* con = ss.constant ? &*ss.constant : nullptr;
  const std::string opt_name = fmt::format("time-optimal ({} s)", g(ss.plan.time(), 4));
  const std::string con_name =
      ss.plan.constant_speed ? fmt::format("best constant speed ({} s)", g(ss.plan.constant_time, 4)) : std::string();
  // one series of a schedule: y(sample) against the distance in mm
  auto series = [](const TorqueAnalysis& a, auto y, std::string label, int color, bool dashed) {
    plot::Series s;
    s.x.reserve(a.series.size());
    s.y.reserve(a.series.size());
    for (const TorqueSample& x : a.series) {
      s.x.push_back(x.s * 1e3);
      s.y.push_back(y(x));
    }
    s.label = std::move(label);
    s.color = plot::palette(color);
    s.width = dashed ? 1.3 : 1.8;
    s.dashed = dashed;
    return s;
  };
  double L = 0.0;
  if (!opt.series.empty()) L = opt.series.back().s * 1e3;
  auto level = [&](double y, std::string label, int color) {
    plot::Series s;
    s.x = {0.0, L};
    s.y = {y, y};
    s.label = std::move(label);
    s.color = plot::palette(color);
    s.width = 1.0;
    s.dashed = true;
    return s;
  };
  auto top = [](const plot::Panel& p) {
    double hi = 0.0;
    for (const plot::Series& s : p.series)
      for (double y : s.y)
        if (std::isfinite(y)) hi = std::max(hi, y);
    return hi;
  };
  // speed
  {
    plot::Panel p = plot::panel("Speed along the path", "distance along the path (mm)", "speed (cm/s)");
    p.series.push_back(series(opt, [](const TorqueSample& x) { return x.st.V * 1e2; }, opt_name, 0, false));
    if (con) p.series.push_back(series(*con, [](const TorqueSample& x) { return x.st.V * 1e2; }, con_name, 1, true));
    if (job_speed) p.series.push_back(level(*job_speed * 1e2, fmt::format("this job's speed ({} cm/s)", g(*job_speed * 1e2, 4)), 3));
    p.ymin = 0.0;
    p.ymax = top(p) * 1.45 + 1e-12;
    f.panels.push_back(std::move(p));
  }
  // step rates
  {
    const MachineModel& m = *job.machine.dynamics;
    plot::Panel p = plot::panel("Motor step rates", "distance along the path (mm)", "steps/s");
    p.series.push_back(series(opt, [](const TorqueSample& x) { return x.radial.step_rate; }, "radial, time-optimal", 0, false));
    p.series.push_back(series(opt, [](const TorqueSample& x) { return x.angular.step_rate; }, "angular, time-optimal", 2, false));
    if (con) {
      p.series.push_back(series(*con, [](const TorqueSample& x) { return x.radial.step_rate; }, "radial, constant", 0, true));
      p.series.push_back(series(*con, [](const TorqueSample& x) { return x.angular.step_rate; }, "angular, constant", 2, true));
    }
    if (m.radial.max_step_rate && m.angular.max_step_rate && *m.radial.max_step_rate == *m.angular.max_step_rate) {
      p.series.push_back(level(*m.radial.max_step_rate, fmt::format("limit of both drives ({} steps/s)", g(*m.radial.max_step_rate, 4)), 6));
    } else {
      if (m.radial.max_step_rate)
        p.series.push_back(level(*m.radial.max_step_rate, fmt::format("radial limit ({} steps/s)", g(*m.radial.max_step_rate, 4)), 6));
      if (m.angular.max_step_rate)
        p.series.push_back(level(*m.angular.max_step_rate, fmt::format("angular limit ({} steps/s)", g(*m.angular.max_step_rate, 4)), 3));
    }
    p.ymin = 0.0;
    p.ymax = top(p) * 1.45 + 1e-12;
    f.panels.push_back(std::move(p));
  }
  // torque ratios
  {
    plot::Panel p = plot::panel("Torque ratios (torque needed / pull-out torque)", "distance along the path (mm)", "|torque ratio|");
    auto rr = [](const TorqueSample& x) { return std::abs(x.radial.ratio); };
    auto ar = [](const TorqueSample& x) { return std::abs(x.angular.ratio); };
    p.series.push_back(series(opt, rr, "radial, time-optimal", 0, false));
    p.series.push_back(series(opt, ar, "angular, time-optimal", 2, false));
    if (con) {
      p.series.push_back(series(*con, rr, "radial, constant", 0, true));
      p.series.push_back(series(*con, ar, "angular, constant", 2, true));
    }
    p.series.push_back(level(limit, fmt::format("limit 1/SF = {}", g(limit, 4)), 6));
    p.ymin = 0.0;
    p.ymax = std::min(top(p), 2.0 * limit) * 1.45 + 1e-12;
    f.panels.push_back(std::move(p));
  }
  return f;
}

plot::Figure torque_figure(const Job& job, const CaseResult& c) {
  plot::Figure f = plot::figure(1100, 820);
  f.rows = 2;
  const double sf = c.verdict.safety_factor;
  for (int axis = 0; axis < 2; ++axis) {
    plot::Panel p = plot::panel(std::string(axis == 0 ? "Radial" : "Angular") + " drive: torque needed and available",
                                "distance along the path (mm)",
                                "torque (N m)");
    plot::Series need, avail, lim;
    for (const TorqueSample& x : c.analysis.series) {
      const AxisDemand& d = axis == 0 ? x.radial : x.angular;
      const double s = x.s * 1e3;
      need.x.push_back(s);
      need.y.push_back(std::abs(d.torque));
      avail.x.push_back(s);
      avail.y.push_back(std::max(0.0, d.pullout));
      lim.x.push_back(s);
      lim.y.push_back(std::max(0.0, d.pullout) / sf);
    }
    need.label = "needed";
    need.color = plot::palette(1);
    need.width = 1.8;
    avail.label = "available (pull-out)";
    avail.color = plot::palette(2);
    avail.width = 1.8;
    lim.label = fmt::format("limit (pull-out / {})", g(sf, 3));
    lim.color = plot::palette(2);
    lim.width = 1.2;
    lim.dashed = true;
    double hi = 0.0;
    for (double y : avail.y) hi = std::max(hi, y);
    for (double y : need.y) hi = std::max(hi, y);
    p.series = {avail, lim, need};
    const Extreme& e = axis == 0 ? c.analysis.radial.ratio : c.analysis.angular.ratio;
    if (std::isfinite(e.value)) {
      const AxisDemand& d = axis == 0 ? e.at.radial : e.at.angular;
      p.series.push_back(plot::marker(e.at.s * 1e3, std::abs(d.torque), "largest ratio", 3, 4, 1.8));
    }
    p.ymin = 0.0;
    p.ymax = hi * 1.6 + 1e-12;
    (void)job;
    f.panels.push_back(p);
  }
  return f;
}

plot::Figure pole_map_figure(const Job& job, const PoleSurvey& sv, double limit, const std::vector<Vec2>& contour,
                             const std::vector<PoleMark>& marks) {
  plot::Figure f = plot::figure(1000, 900);
  plot::Panel p = plot::panel("Area error by machine-pole position",
                              "machine pole x - contour pole x (mm)",
                              "machine pole y - contour pole y (mm)",
                              true);
  plot::Map m, w;
  m.nx = w.nx = sv.nx;
  m.ny = w.ny = sv.ny;
  m.x0 = w.x0 = sv.box.x0 * 1e3;
  m.x1 = w.x1 = sv.box.x1 * 1e3;
  m.y0 = w.y0 = sv.box.y0 * 1e3;
  m.y1 = w.y1 = sv.box.y1 * 1e3;
  m.levels = 9;
  m.colorbar_label = "mm^2";
  plot::Series over;
  over.label = "torque over the limit";
  over.color = plot::palette(6);
  over.width = 0;
  over.marker = 5;
  over.marker_scale = 0.7;
  for (int iy = 0; iy < sv.ny; ++iy)
    for (int ix = 0; ix < sv.nx; ++ix) {
      const PoleValue& v = sv.cells[static_cast<size_t>(iy) * static_cast<size_t>(sv.nx) + static_cast<size_t>(ix)];
      const bool geo = v.computed && v.geometry_margin >= 0.0;
      m.z.push_back(geo && v.area_m2 >= 0.0 ? v.area_m2 * 1e6 : kNaN);
      const bool tq = geo && v.torque_computed && v.torque.computed;
      w.z.push_back(tq ? std::min(v.torque.worst, 1e6) : kNaN);
      if (geo && (!tq || !(v.torque.worst <= limit))) {
        const Vec2 q = sv.pole(ix, iy);
        over.x.push_back(q.x * 1e3);
        over.y.push_back(q.y * 1e3);
      }
    }
  p.map = m;
  plot::Isoline iso;
  iso.field = w;
  iso.level = limit;
  iso.color = plot::palette(3);
  p.isolines.push_back(iso);
  plot::Series c;
  for (const Vec2& v : contour) {
    c.x.push_back(v.x * 1e3);
    c.y.push_back(v.y * 1e3);
  }
  c.label = "contour (its own frame)";
  c.color = plot::palette(6);
  c.width = 1.6;
  p.series.push_back(c);
  if (!over.x.empty()) p.series.push_back(over);
  plot::Series il;
  il.label = fmt::format("worst torque ratio = {}", g(limit, 3));
  il.color = plot::palette(3);
  il.width = 2.5;
  p.series.push_back(il);
  for (const PoleMark& k : marks)
    p.series.push_back(plot::marker(k.pole.x * 1e3, k.pole.y * 1e3, k.label, k.color, k.marker));
  // the extent: the surveyed box and the marked poles (the contour is clipped), with room for the legend above
  double x0 = sv.box.x0, x1 = sv.box.x1, y0 = sv.box.y0, y1 = sv.box.y1;
  for (const PoleMark& k : marks) {
    x0 = std::min(x0, k.pole.x), x1 = std::max(x1, k.pole.x);
    y0 = std::min(y0, k.pole.y), y1 = std::max(y1, k.pole.y);
  }
  const double dx = x1 - x0, dy = y1 - y0;
  p.xmin = (x0 - 0.05 * dx) * 1e3;
  p.xmax = (x1 + 0.05 * dx) * 1e3;
  p.ymin = (y0 - 0.05 * dy) * 1e3;
  p.ymax = (y1 + 0.45 * dy) * 1e3;
  (void)job;
  f.panels.push_back(p);
  return f;
}

plot::Figure tradeoff_figure(const PoleSurvey& sv, const std::vector<ParetoPoint>& front, double limit,
                             const std::vector<std::pair<ParetoPoint, PoleMark>>& marks) {
  plot::Figure f = plot::figure(1000, 650);
  plot::Panel p = plot::panel("Accuracy against torque: every surveyed pole, and the best trade-offs",
                              "worst torque ratio (needed / pull-out)",
                              "area error (mm^2)");
  plot::Series all;
  all.label = "surveyed poles";
  all.color = plot::palette(5);
  all.width = 0;
  all.marker = 17;
  all.marker_scale = 0.8;
  double x_hi = limit, y_lo = std::numeric_limits<double>::infinity(), y_hi = -y_lo;
  for (const PoleValue& v : sv.cells)
    if (v.feasible() && v.area_m2 >= 0.0 && v.torque_computed && v.torque.computed && std::isfinite(v.torque.worst)) {
      all.x.push_back(v.torque.worst);
      all.y.push_back(v.area_m2 * 1e6);
    }
  plot::Series fr;
  fr.label = "best trade-offs (Pareto front)";
  fr.color = plot::palette(0);
  fr.width = 2.0;
  fr.marker = 4;
  fr.marker_scale = 0.9;
  for (const ParetoPoint& x : front) {
    fr.x.push_back(x.v.torque.worst);
    fr.y.push_back(x.v.area_m2 * 1e6);
  }
  for (const auto* s : {&all, &fr})
    for (size_t i = 0; i < s->x.size(); ++i) {
      x_hi = std::max(x_hi, s->x[i]);
      y_lo = std::min(y_lo, s->y[i]);
      y_hi = std::max(y_hi, s->y[i]);
    }
  if (!std::isfinite(y_lo)) y_lo = 0.0, y_hi = 1.0;
  p.series.push_back(all);
  p.series.push_back(fr);
  plot::Series l;
  l.x = {limit, limit};
  l.y = {y_lo, y_hi};
  l.label = fmt::format("torque limit {}", g(limit, 3));
  l.color = plot::palette(3);
  l.dashed = true;
  l.width = 1.6;
  p.series.push_back(l);
  for (const auto& [pt, k] : marks)
    if (pt.v.area_m2 >= 0.0 && pt.v.torque_computed && std::isfinite(pt.v.torque.worst))
      p.series.push_back(plot::marker(pt.v.torque.worst, pt.v.area_m2 * 1e6, k.label, k.color, k.marker));
  double x_lo = limit;
  for (const auto* s : {&all, &fr})
    for (double x : s->x) x_lo = std::min(x_lo, x);
  p.xmin = std::max(0.0, x_lo - 0.08 * (x_hi - x_lo));
  p.xmax = x_hi + 0.08 * (x_hi - x_lo) + 1e-12;
  const double dy = y_hi - y_lo;
  p.ymin = y_lo - 0.05 * dy;
  p.ymax = y_hi + 0.45 * dy + 1e-9;
  f.panels.push_back(p);
  return f;
}

}  // namespace polarcam::cli
