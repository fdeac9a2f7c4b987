#include "report/compare_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "report/html.hpp"
#include "io/output.hpp"
#include "report/plot.hpp"

namespace polarcam {
namespace {

using html::escape;

std::string fmt(double v, int prec = 5) { return cli::significant(v, prec); }

std::string cartesian_name(const Comparison& c) {
  return c.cartesian.method == "dda" ? "Cartesian (DDA)" : "Cartesian (exact times)";
}

// Colours: the polar machine orange, the Cartesian one blue, the contour black (Okabe-Ito).
const plot::Color kPolar = plot::palette(1), kCartesian = plot::palette(0), kContour = plot::palette(6);

std::vector<plot::Series> runs_series(const std::vector<std::vector<Vec2>>& runs, const std::string& label,
                                      plot::Color col, double width, int marker, double scale = 1e3) {
  std::vector<plot::Series> out;
  for (const auto& r : runs) {
    plot::Series s;
    for (const Vec2& p : r) {
      s.x.push_back(p.x * scale);
      s.y.push_back(p.y * scale);
    }
    s.color = col;
    s.width = width;
    s.marker = marker;
    s.marker_scale = 0.6;
    if (out.empty()) s.label = label;
    out.push_back(std::move(s));
  }
  return out;
}

// The corner of a window with the fewest points of the drawn lines near it (for the legend).
plot::Panel::Legend emptiest_corner(const std::vector<plot::Series>& series, double x0, double x1, double y0, double y1) {
  int count[4] = {0, 0, 0, 0};  // top right, top left, bottom right, bottom left
  const double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1), wx = 0.5 * (x1 - x0), wy = 0.5 * (y1 - y0);
  for (const auto& s : series)
    for (size_t i = 0; i < s.x.size(); ++i) {
      const double dx = (s.x[i] - xm) / wx, dy = (s.y[i] - ym) / wy;
      if (std::abs(dx) > 1 || std::abs(dy) > 1 || (std::abs(dx) < 0.2 && std::abs(dy) < 0.2)) continue;
      count[(dy > 0 ? 0 : 2) + (dx > 0 ? 0 : 1)] += 1;
    }
  const int best = static_cast<int>(std::min_element(count, count + 4) - count);
  static const plot::Panel::Legend corners[4] = {plot::Panel::Legend::top_right, plot::Panel::Legend::top_left,
                                                 plot::Panel::Legend::bottom_right, plot::Panel::Legend::bottom_left};
  return corners[best];
}

plot::Figure overview_figure(const Comparison& c) {
  plot::Figure f = plot::figure(900, 680);
  plot::Panel p = plot::panel("The tool path and where the details are", "x (mm), contour frame", "y (mm)", true);
  plot::Series s;
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (const Vec2& q : c.outline) {
    s.x.push_back(q.x * 1e3);
    s.y.push_back(q.y * 1e3);
    xmin = std::min(xmin, q.x * 1e3), xmax = std::max(xmax, q.x * 1e3);
    ymin = std::min(ymin, q.y * 1e3), ymax = std::max(ymax, q.y * 1e3);
  }
  s.color = kContour;
  s.width = 1.5;
  s.label = "tool path";
  p.series.push_back(s);
  for (int w = 0; w < 2; ++w) {
    const DetailWindow& win = c.windows[w];
    // the detail windows, drawn larger than they are so that they can be seen
    const double h = std::max(win.half * 1e3, 0.015 * std::max(xmax - xmin, ymax - ymin));
    plot::Series b;
    const double cx = win.center.x * 1e3, cy = win.center.y * 1e3;
    b.x = {cx - h, cx + h, cx + h, cx - h, cx - h};
    b.y = {cy - h, cy - h, cy + h, cy + h, cy - h};
    b.color = w == 0 ? kPolar : kCartesian;
    b.width = 2.5;
    b.label = w == 0 ? "polar machine's worst point" : "Cartesian machine's worst point";
    p.series.push_back(b);
  }
  // room for the legend above the path
  const double span = std::max(xmax - xmin, ymax - ymin);
  p.ymax = ymax + 0.35 * span;
  p.ymin = ymin - 0.05 * span;
  p.xmin = xmin - 0.05 * span;
  p.xmax = xmax + 0.05 * span;
  f.panels.push_back(p);
  return f;
}

plot::Figure detail_figure(const Comparison& c) {
  plot::Figure f = plot::figure(1400, 720);
  f.cols = 2;
  f.rows = 1;
  for (int w = 0; w < 2; ++w) {
    const DetailWindow& win = c.windows[w];
    plot::Panel p = plot::panel(w == 0 ? "At the polar machine's worst point" : "At the Cartesian machine's worst point",
                                "x (mm)",
                                "y (mm)",
                                true);
    const double cx = win.center.x * 1e3, cy = win.center.y * 1e3, h = win.half * 1e3;
    p.xmin = cx - h;
    p.xmax = cx + h;
    p.ymin = cy - h;
    p.ymax = cy + h;
    for (auto& s : runs_series(c.contour_in[w], "tool path", kContour, 2.5, 0)) p.series.push_back(s);
    for (auto& s : runs_series(c.polar.detail[w], "polar", kPolar, 1.8, 0)) p.series.push_back(s);
    for (auto& s : runs_series(c.cartesian.detail[w], cartesian_name(c), kCartesian, 1.8, 0)) p.series.push_back(s);
    p.legend = emptiest_corner(p.series, cx - h, cx + h, cy - h, cy + h);
    plot::Series mark;
    mark.x = {cx};
    mark.y = {cy};
    mark.width = 0;
    mark.marker = 4;
    mark.marker_scale = 1.6;
    mark.color = w == 0 ? kPolar : kCartesian;
    mark.label = "worst point";
    p.series.push_back(mark);
    f.panels.push_back(p);
  }
  return f;
}

plot::Figure speed_figure(const Comparison& c) {
  plot::Figure f = plot::figure(1300, 760);
  f.cols = 1;
  f.rows = 2;
  const double V = c.nominal_speed * 1e3;
  double lo = V, hi = V;
  for (const MachineSide* s : {&c.polar, &c.cartesian}) {
    lo = std::min(lo, s->speed.min_mps * 1e3);
    hi = std::max(hi, s->speed.max_mps * 1e3);
  }
  const double pad = std::max(0.05 * (hi - lo), 0.002 * V), room = std::max(0.45 * (hi - lo), 0.01 * V);
  for (const MachineSide* s : {&c.polar, &c.cartesian}) {
    plot::Panel p;
    const bool polar = s == &c.polar;
    p.title = std::string(polar ? "Polar machine" : cartesian_name(c)) + ": speed from the pulse rates (RMS deviation " +
              fmt(s->speed.rms_dev_mps * 1e3, 3) + " mm/s)";
    p.xlabel = "time (s)";
    p.ylabel = "speed (mm/s)";
    p.ymin = lo - pad;
    p.ymax = hi + room;  // the legend goes above the data
    p.hlines = {V};
    if (s->trace) {
      const SpeedTrace& t = *s->trace;
      plot::Series mn, mx, mean;
      for (int i = 0; i < t.bins(); ++i) {
        if (!(t.sw[static_cast<size_t>(i)] > 0.0)) continue;
        const double x = (i + 0.5) * t.t_end_s / t.bins();
        mn.x.push_back(x);
        mn.y.push_back(t.vmin[static_cast<size_t>(i)] * 1e3);
        mx.x.push_back(x);
        mx.y.push_back(t.vmax[static_cast<size_t>(i)] * 1e3);
        mean.x.push_back(x);
        mean.y.push_back(t.mean(i) * 1e3);
      }
      const plot::Color col = polar ? kPolar : kCartesian;
      mx.color = mn.color = plot::palette(polar ? 4 : 5);
      mx.width = mn.width = 1.0;
      mx.label = "fastest and slowest step in each time slice";
      mean.color = col;
      mean.width = 2.0;
      mean.label = "mean in each slice";
      p.series = {mx, mn, mean};
    }
    f.panels.push_back(p);
  }
  return f;
}

std::string winner_text(const Comparison& c, const std::string& w) {
  if (w == "tie") return "tie";
  return w == "polar" ? "polar" : cartesian_name(c);
}

void verdict_table(html::Report& r, const Comparison& c) {
  std::string t = "<table class=\"verdicts\">\n<thead><tr><th>attribute</th><th>polar machine</th><th>" +
                  escape(cartesian_name(c)) + "</th><th>better for this job</th><th>why</th></tr></thead>\n<tbody>\n";
  for (const AttributeVerdict& v : c.verdicts) {
    auto cell = [&](const std::string& side, const std::string& text) {
      const bool win = v.winner == side;
      return std::string("<td") + (win ? " style=\"background:#dff3e3;font-weight:600\"" : "") + ">" + escape(text) + "</td>";
    };
    t += "<tr><td>" + escape(v.attribute) + "</td>" + cell("polar", v.polar) + cell("cartesian", v.cartesian) +
         "<td><strong>" + escape(winner_text(c, v.winner)) + "</strong></td><td>" + escape(v.why) + "</td></tr>\n";
  }
  t += "</tbody></table>\n";
  r.raw(t);
}

}  // namespace

void write_compare_report(const Comparison& c, const std::string& path) {
  const MachineSide& P = c.polar;
  const MachineSide& Q = c.cartesian;
  html::Report r("Polar or Cartesian? " + std::filesystem::path(c.job_file).filename().string());
  r.paragraph("Job " + c.job_file + ": the " + (c.closed ? "closed" : "open") + " tool path of " + c.contour + ", " +
              fmt(c.path_length_m * 1e3, 6) + " mm long, cut at " + fmt(c.nominal_speed * 1e3) +
              " mm/s on two machines, each measured the same way against the same tool path.");
  r.raw("<ul><li><strong>Polar machine</strong> (the job's): " + escape(P.grid) + "; stepping rule " + escape(P.method) +
        ".</li><li><strong>" + escape(cartesian_name(c)) + "</strong>: " + escape(Q.grid) +
        (Q.method == "dda" ? " (the contour approximated by lines and arcs, a feed accumulator driving linear and "
                             "circular digital differential analysers, as numerical controls of the thesis's era did)"
                           : " (every step at the exact time the tool centre crosses the middle between two nodes)") +
        ".</li></ul>\n");

  int wp = 0, wc = 0, ties = 0;
  for (const AttributeVerdict& v : c.verdicts) (v.winner == "polar" ? wp : v.winner == "cartesian" ? wc : ties) += 1;
  r.heading(2, "Which machine is better for this job");
  const std::string tied = ties == 0 ? "none is a tie" : ties == 1 ? "one is a tie" : std::to_string(ties) + " are ties";
  r.paragraph("Of the " + std::to_string(c.verdicts.size()) + " attributes below, the polar machine is better on " +
              std::to_string(wp) + ", the " + cartesian_name(c) + " machine on " + std::to_string(wc) + ", and " +
              tied + ". The attributes of the thesis's Table 3.1 (contouring speed, speed "
              "scaling, size scaling, accuracy) are measured here, not argued.");
  verdict_table(r, c);

  r.heading(2, "Measurements side by side");
  auto n = [](uint64_t v) { return cli::thousands(v); };
  std::vector<std::vector<std::string>> rows = {
      {"steps " + P.axis[0] + " | " + Q.axis[0], n(P.steps[0]), n(Q.steps[0])},
      {"steps " + P.axis[1] + " | " + Q.axis[1], n(P.steps[1]), n(Q.steps[1])},
      {"steps in all", n(P.steps_total()), n(Q.steps_total())},
      {"contouring time (s)", fmt(P.duration_s, 7), fmt(Q.duration_s, 7)},
      {"slowest speed (mm/s)", fmt(P.speed.min_mps * 1e3), fmt(Q.speed.min_mps * 1e3)},
      {"fastest speed (mm/s)", fmt(P.speed.max_mps * 1e3), fmt(Q.speed.max_mps * 1e3)},
      {"mean speed (mm/s)", fmt(P.speed.mean_mps * 1e3), fmt(Q.speed.mean_mps * 1e3)},
      {"RMS deviation from " + fmt(c.nominal_speed * 1e3) + " mm/s (mm/s)", fmt(P.speed.rms_dev_mps * 1e3, 4),
       fmt(Q.speed.rms_dev_mps * 1e3, 4)},
      {"area error (mm²)", fmt(P.area_m2 * 1e6), fmt(Q.area_m2 * 1e6)},
      {"largest deviation (mm)", fmt(P.deviation_m * 1e3, 4), fmt(Q.deviation_m * 1e3, 4)},
      {"  where (x, y in mm, contour frame)", fmt(P.deviation_at.x * 1e3, 6) + ", " + fmt(P.deviation_at.y * 1e3, 6),
       fmt(Q.deviation_at.x * 1e3, 6) + ", " + fmt(Q.deviation_at.y * 1e3, 6)},
      {"highest step rate " + P.axis[0] + " | " + Q.axis[0] + " (Hz)", fmt(P.rates[0].max_rate_hz), fmt(Q.rates[0].max_rate_hz)},
      {"highest step rate " + P.axis[1] + " | " + Q.axis[1] + " (Hz)", fmt(P.rates[1].max_rate_hz), fmt(Q.rates[1].max_rate_hz)},
      {"reversals " + P.axis[0] + " | " + Q.axis[0], n(P.rates[0].reversals), n(Q.rates[0].reversals)},
      {"reversals " + P.axis[1] + " | " + Q.axis[1], n(P.rates[1].reversals), n(Q.rates[1].reversals)},
      {"tape (bytes)", n(P.tape_bytes), n(Q.tape_bytes)},
      {"resolution at the worst point (mm)", fmt(P.resolution_worst_m * 1e3, 4), fmt(Q.resolution_worst_m * 1e3, 4)},
  };
  r.table({"", "polar", cartesian_name(c)}, rows,
          "Speeds are measured from the pulse rates of each tape (step length over the time between two steps of an "
          "axis); step rates are those of consecutive steps in the same direction; a reversal is an axis changing "
          "direction (where the path turns, or grazes a step level and steps out and back).");

  r.heading(2, "Where the machines stray from the contour");
  r.figure(overview_figure(c), "The tool path in the contour's own frame, and the places shown magnified below: "
                               "where each machine strays farthest from it (the squares are drawn larger than the "
                               "details).",
           "the tool path and the places of the largest deviations");
  const double zoom_mm = 2e3 * c.windows[0].half;
  r.figure(detail_figure(c),
           "Both machines' paths over the tool path (black), in squares " + fmt(zoom_mm, 3) +
               " mm wide: the polar machine's (orange) is a staircase of radial steps and short arcs about its pole, "
               "the Cartesian machine's (blue) a staircase of x and y steps. The circle marks the worst point.",
           "both staircases near the largest deviations");

  r.heading(2, "Tangential speed along the path");
  r.figure(speed_figure(c),
           "The speed of each machine from its pulse rates, in " + std::to_string(P.trace ? P.trace->bins() : 0) +
               " time slices: the mean in each slice, and the fastest and slowest step interval in it. The dashed "
               "line is the programmed speed. A steady line means the cutter moves at a constant speed, which is "
               "what a constant chip load and surface finish need.",
           "speed along the path of both machines");

  r.heading(2, "How it was measured");
  r.raw(
      "<ul>"
      "<li><strong>Area error</strong>: the area enclosed between the tool path and the machine's quasi-static path "
      "(straight unit steps, and for the polar machine arcs about its pole), computed exactly; where the two cross, "
      "every enclosed piece counts positive.</li>"
      "<li><strong>Deviation</strong>: the largest distance from any point of the machine's path to the tool path.</li>"
      "<li><strong>Speed</strong>: between two pulses of an axis the axis moves one step in the time between them; "
      "the tool's speed is the hypotenuse of both axes' speeds at the same instant.</li>"
      "<li><strong>Speed scaling</strong>: the tape played K times faster (every interval divided by K), or for the "
      "DDA control the program interpolated again with new feed words, then measured as above.</li>"
      "<li><strong>Size scaling</strong>: the machine's node indices on one axis (or both) multiplied by P/Q and "
      "rounded; the size is the bounding box of the nodes the scaled tape visits, and its error is measured against "
      "the contour scaled by P/Q.</li>"
      "<li>Not measured here (Table 3.1 lists them as design properties): the work area (circular for the polar "
      "machine), the reference position (the polar machine's radial reference is fixed, its angular one floats), "
      "power utilisation of the drives and cost.</li>"
      "</ul>\n");
  r.paragraph("Made by polarcam compare; the model and the definitions are in docs/compare.md of the polarcam sources.");
  r.save(path);
}

}  // namespace polarcam
