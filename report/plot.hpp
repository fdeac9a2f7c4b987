#pragma once
// Figures for reports and the CLI, drawn with PLplot (cairo devices): line and marker series, filled contour
// maps with contour lines, several panels per figure. Written as PNG or SVG by the file name's extension, all
// or nothing. PLplot keeps global state, so rendering is serialised internally.
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace polarcam::plot {

struct Color {
  int r = 0, g = 0, b = 0;
};
// A qualitative palette (colour-blind safe, Okabe-Ito): index 0..7.
Color palette(int i);

struct Series {
  std::vector<double> x, y;
  std::string label;        // shown in the legend when not empty
  Color color = palette(0);
  double width = 1.5;       // line width; 0 draws markers only
  int marker = 0;           // 0 none; otherwise a PLplot symbol code (e.g. 2 plus, 4 circle, 17 dot)
  double marker_scale = 1.0;
  bool dashed = false;
};

// Values on a regular grid: z[iy * nx + ix] at x = x0 + ix (x1 - x0)/(nx - 1), y likewise. NaN cells are left
// blank (outside a constraint, say).
struct Map {
  int nx = 0, ny = 0;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  std::vector<double> z;
  int levels = 12;          // filled bands
  bool log_scale = false;   // bands evenly spaced in log10(z)
  std::string colorbar_label;
};

// One contour line of a field on a regular grid (z as in Map), e.g. the boundary of a region where a constraint
// holds. Label it with an empty Series of the same colour (a legend entry).
struct Isoline {
  Map field;                // levels, log_scale and colorbar_label are not used
  double level = 0.0;
  Color color = palette(6);
  double width = 2.5;
};

struct Panel {
  std::string title, xlabel, ylabel;
  std::vector<Series> series;
  std::optional<Map> map;   // drawn under the series
  std::vector<Isoline> isolines;  // drawn over the map, under the series
  bool equal_aspect = false;
  enum class Legend { top_right, top_left, bottom_right, bottom_left };
  Legend legend = Legend::top_right;             // inside the plot area
  std::optional<double> xmin, xmax, ymin, ymax;  // default: the data's extent with a margin
  std::vector<double> hlines;                    // horizontal reference lines (dashed grey)
};

struct Figure {
  int width = 1000, height = 700;  // pixels
  int cols = 1, rows = 1;
  std::vector<Panel> panels;       // row-major, cols * rows at most
};

// A figure of the given size (pixels), one panel per cell; a panel with its title and axis labels.
inline Figure figure(int width, int height) {
  Figure f;
  f.width = width;
  f.height = height;
  return f;
}
inline Panel panel(std::string title, std::string xlabel, std::string ylabel, bool equal_aspect = false) {
  Panel p;
  p.title = std::move(title);
  p.xlabel = std::move(xlabel);
  p.ylabel = std::move(ylabel);
  p.equal_aspect = equal_aspect;
  return p;
}

// One marked point (no line): a marker of PLplot symbol `symbol` in palette colour `color`.
inline Series marker(double x, double y, std::string label, int color, int symbol, double scale = 2.0) {
  Series s;
  s.x = {x};
  s.y = {y};
  s.label = std::move(label);
  s.color = palette(color);
  s.width = 0;
  s.marker = symbol;
  s.marker_scale = scale;
  return s;
}

// Renders to `path` (.png or .svg); throws InputError for another extension, DeviceError for an unwritable file.
void save(const Figure& f, const std::string& path);
// Checks a plot's file name before any work: InputError unless .png or .svg, DeviceError when it cannot be written
// (check_output_path).
void check_plot_path(const std::string& path);
// The format of a plot's file name: "png" or "svg" (InputError otherwise).
std::string plot_format(const std::string& path);
// Renders to bytes in the given format ("png" or "svg").
std::string render(const Figure& f, const std::string& format);

}  // namespace polarcam::plot
