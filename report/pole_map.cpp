#include "report/pole_map.hpp"

#include <charconv>
#include <cmath>
#include <numbers>

namespace polarcam {

std::string map_csv(const ObjectiveMap& m, PoleObjective objective) {
  std::string out = "x_mm,y_mm,C_mm,beta_rad,feasible,objective,area_error_mm2,margin_mm\n";
  // nine significant digits, printf's %.9g (std::to_chars with a precision is specified to write the same
  // characters, without the locale and a few times faster: a 401 x 401 map writes over a million numbers)
  auto put = [&out](double v) {
    char b[40];
    const auto r = std::to_chars(b, b + sizeof b, v, std::chars_format::general, 9);
    out.append(b, r.ptr);
  };
  auto num = [&](double v, double scale) {  // empty where there is no value
    if (std::isfinite(v)) put(v * scale);
  };
  const double oscale = objective == PoleObjective::area ? 1e6 : 1.0;
  // a torque objective's search value of 1e3 or more stands for an infinite objective (torque_search_value)
  auto value = [&](double v) { return is_torque_objective(objective) && v >= 1e3 ? NAN : v; };
  for (int iy = 0; iy < m.ny; ++iy)
    for (int ix = 0; ix < m.nx; ++ix) {
      const size_t i = static_cast<size_t>(iy) * static_cast<size_t>(m.nx) + static_cast<size_t>(ix);
      const double x = m.box.x0 + (m.box.x1 - m.box.x0) * ix / (m.nx - 1);
      const double y = m.box.y0 + (m.box.y1 - m.box.y0) * iy / (m.ny - 1);
      double beta = std::atan2(y, x);
      if (beta < 0) beta += 2.0 * std::numbers::pi;
      put(x * 1e3);
      out += ',';
      put(y * 1e3);
      out += ',';
      put(std::hypot(x, y) * 1e3);
      out += ',';
      put(beta);
      out += std::isfinite(m.value[i]) ? ",1," : ",0,";
      num(value(m.value[i]), oscale);
      out += ',';
      num(m.area[i], 1e6);
      out += ',';
      num(m.margin[i], 1e3);
      out += '\n';
    }
  return out;
}

plot::Figure map_figure(const ObjectiveMap& m, PoleObjective objective, const std::vector<Vec2>& contour,
                        const Placement& start, const PlacementResult& r, const std::string& title) {
  plot::Figure f = plot::figure(1000, 900);
  plot::Panel p = plot::panel(title,
                              "machine pole x - contour pole x (mm)",
                              "machine pole y - contour pole y (mm)",
                              true);
  plot::Map mp;
  mp.nx = m.nx;
  mp.ny = m.ny;
  mp.x0 = m.box.x0 * 1e3;
  mp.x1 = m.box.x1 * 1e3;
  mp.y0 = m.box.y0 * 1e3;
  mp.y1 = m.box.y1 * 1e3;
  mp.z = m.value;
  if (objective == PoleObjective::area)
    for (double& z : mp.z) z *= 1e6;
  if (is_torque_objective(objective))
    for (double& z : mp.z)
      if (z >= 1e3) z = NAN;  // an infinite objective (torque_search_value)
  mp.levels = 9;  // the thesis's topographic contours are numbered 1 to 9
  mp.colorbar_label = objective == PoleObjective::area ? "mm^2" : (objective == PoleObjective::f1 ? "F1" : "");
  p.map = mp;
  plot::Series c;
  for (const Vec2& v : contour) {
    c.x.push_back(v.x * 1e3);
    c.y.push_back(v.y * 1e3);
  }
  c.label = "contour";
  c.color = plot::palette(6);
  c.width = 2.0;
  p.series.push_back(c);
  if (r.path.size() > 1) {
    plot::Series h;
    for (const Vec2& v : r.path) {
      h.x.push_back(v.x * 1e3);
      h.y.push_back(v.y * 1e3);
    }
    h.label = "Hooke-Jeeves bases";
    h.color = plot::palette(5);
    h.width = 1.0;
    h.marker = 17;
    p.series.push_back(h);
  }
  p.series.push_back(plot::marker(start.pole().x * 1e3, start.pole().y * 1e3, "job's placement", 1, 4, 1.5));
  p.series.push_back(plot::marker(r.pole.x * 1e3, r.pole.y * 1e3, "optimum", 3, 2, 2.5));
  f.panels.push_back(p);
  return f;
}

}  // namespace polarcam
