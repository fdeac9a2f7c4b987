#include "report/template_figure.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cam/format.hpp"
#include "digitizer/template_speed.hpp"

namespace polarcam {

plot::Figure template_speed_figure(const TemplateFigureOptions& o) {
  plot::Figure fig = plot::figure(1000, 700);
  plot::Panel p = plot::panel("Template digitizer: contouring speed error against rho* (Fahim, Fig. 3.2, Eq. 3.3 "
                              "with the factor 2)",
                              "rho* = radius of curvature / template thickness",
                              "speed error |v/V_t - 1| (%)");
  const int n = 600;
  for (size_t k = 0; k < o.rr_stars.size(); ++k) {
    const double rr = o.rr_stars[k];
    const plot::Color color = plot::palette(static_cast<int>(k % 8));
    for (CurvatureSide side : {CurvatureSide::roller, CurvatureSide::other}) {
      // from the tightest radius the rollers follow: rho* = R_r* (3.3a, the roller stops), 1 + R_r* (3.3b, the
      // pressure roller just fits on the concave face)
      const double lo = side == CurvatureSide::roller ? rr : 1.0 + rr;
      if (!(lo < o.rho_star_max)) continue;
      plot::Series s;
      s.color = color;
      s.dashed = side == CurvatureSide::other;
      s.label = "R_r* = " + significant(rr, 3) + (side == CurvatureSide::roller ? ", centre on the roller's side (3.3a)"
                                                                                 : ", centre on the other side (3.3b)");
      for (int i = 0; i <= n; ++i) {
        // denser near the left end, where the curves are steep
        const double f = static_cast<double>(i) / n;
        const double rho = lo + (o.rho_star_max - lo) * f * f;
        s.x.push_back(rho);
        s.y.push_back(100.0 * std::abs(template_v_star(rho, rr, side) - 1.0));
      }
      p.series.push_back(std::move(s));
      if (side == CurvatureSide::other) {
        // Eq. 3.3b below 1 + R_r*, where the pressure roller no longer fits, down to the 200 % the thesis quotes
        // (at rho* = (2 R_r* + 3) / 4): thin, unlabelled
        plot::Series beyond;
        beyond.color = color;
        beyond.dashed = true;
        beyond.width = 0.6;
        const double from = (2.0 * rr + 3.0) / 4.0;
        for (int i = 0; i <= 100; ++i) {
          const double rho = from + (lo - from) * i / 100.0;
          beyond.x.push_back(rho);
          beyond.y.push_back(100.0 * std::abs(template_v_star(rho, rr, side) - 1.0));
        }
        p.series.push_back(std::move(beyond));
      }
      if (o.mark_rho_star && *o.mark_rho_star >= lo && *o.mark_rho_star <= o.rho_star_max) {
        const double y = 100.0 * std::abs(template_v_star(*o.mark_rho_star, rr, side) - 1.0);
        plot::Series m = plot::marker(*o.mark_rho_star, y, "", static_cast<int>(k % 8), 4, 0.9);
        m.color = color;
        p.series.push_back(std::move(m));
      }
    }
  }
  p.hlines = {10.0};
  p.xmin = 0.0;
  p.xmax = o.rho_star_max;
  p.ymin = 0.0;
  p.ymax = 200.0;
  fig.panels.push_back(std::move(p));
  return fig;
}

}  // namespace polarcam
