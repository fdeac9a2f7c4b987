#include "report/preview_figure.hpp"

#include <cmath>

#include "report/plot.hpp"

namespace polarcam::cli {
namespace {

plot::Series circle(double r, const std::string& label) {
  plot::Series s;
  for (int i = 0; i <= 720; ++i) {
    s.x.push_back(r * std::cos(i * M_PI / 360));
    s.y.push_back(r * std::sin(i * M_PI / 360));
  }
  s.label = label;
  s.color = {150, 150, 150};
  s.width = 1.0;
  s.dashed = true;
  return s;
}

plot::Series line(const Polyline& p, const std::string& label, int color, double width) {
  plot::Series s;
  s.x = p.x;
  s.y = p.y;
  s.label = label;
  s.color = plot::palette(color);
  s.width = width;
  return s;
}

}  // namespace

plot::Figure preview_figure(const Preview& pv) {
  plot::Figure f = plot::figure(1000, 1000);
  plot::Panel p = plot::panel(pv.title, "x (mm)", "y (mm)", true);
  if (pv.r_max_mm) p.series.push_back(circle(*pv.r_max_mm, "work area"));
  if (pv.r_min_mm && *pv.r_min_mm > 0) p.series.push_back(circle(*pv.r_min_mm, ""));
  for (size_t i = 0; i < pv.path.size(); ++i) p.series.push_back(line(pv.path[i], i == 0 ? "tool path" : "", 1, 2.5));
  for (size_t i = 0; i < pv.stepped.size(); ++i)
    p.series.push_back(line(pv.stepped[i], i == 0 ? "stepped motion" : "", 0, 0.8));
  for (size_t i = 0; i < pv.rapids.size(); ++i) {
    plot::Series s = line(pv.rapids[i], i == 0 ? "rapid move, tool up" : "", 3, 1.2);
    s.dashed = true;
    p.series.push_back(std::move(s));
  }
  for (size_t i = 0; i < pv.slowed.size(); ++i)
    p.series.push_back(line(pv.slowed[i], i == 0 ? "below the requested speed" : "", 5, 3.0));
  p.series.push_back(plot::marker(pv.start[0], pv.start[1], "start", 2, 4, 2.5));
  p.series.push_back(plot::marker(pv.end[0], pv.end[1], "end", 5, 17, 2.5));
  if (pv.r_max_mm) {
    const double m = *pv.r_max_mm * 1.05;
    p.xmin = -m, p.xmax = m, p.ymin = -m, p.ymax = m;
  }
  f.panels.push_back(std::move(p));
  return f;
}

void save_preview(const Preview& pv, const std::string& path) { plot::save(preview_figure(pv), path); }

}  // namespace polarcam::cli
