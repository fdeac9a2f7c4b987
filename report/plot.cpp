#include "report/plot.hpp"

#include <plplot/plstream.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <mutex>

#include "io/output.hpp"
#include "cam/error.hpp"

namespace polarcam::plot {

Color palette(int i) {
  static const Color c[] = {{0, 114, 178}, {213, 94, 0}, {0, 158, 115}, {204, 121, 167},
                            {230, 159, 0}, {86, 180, 233}, {0, 0, 0},   {240, 228, 66}};
  return c[((i % 8) + 8) % 8];
}

namespace {

std::mutex& plplot_mutex() {
  static std::mutex m;
  return m;
}

struct Extent {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  void add(double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
};

// cmap0 indices: 0 background (white), 1 foreground (black), 2 grey, 3..15 isolines, 16.. one per series (so
// that the legend, drawn last, finds every series' own colour)
constexpr int kIsolineColor = 3, kSeriesColor = 16, kColors = 256;

// The current viewport in millimetres on the page and its world coordinates: markers and legend swatches are
// sized in millimetres, whatever the axes' units.
struct Frame {
  double vx0 = 0, vx1 = 1, vy0 = 0, vy1 = 1;  // viewport, mm
  double wx0 = 0, wx1 = 1, wy0 = 0, wy1 = 1;  // world
  double ch = 3;                              // character height, mm
  static Frame of(plstream& pls, int cols, int rows) {
    Frame f;
    PLFLT sx0, sx1, sy0, sy1, dx0, dx1, dy0, dy1, def, ht;
    pls.gspa(sx0, sx1, sy0, sy1);  // the subpage, mm
    pls.gvpd(dx0, dx1, dy0, dy1);  // the viewport, normalised device coordinates of the page
    const double W = (sx1 - sx0) * std::max(1, cols), H = (sy1 - sy0) * std::max(1, rows);
    f.vx0 = dx0 * W, f.vx1 = dx1 * W, f.vy0 = dy0 * H, f.vy1 = dy1 * H;
    pls.gvpw(f.wx0, f.wx1, f.wy0, f.wy1);
    pls.gchr(def, ht);
    f.ch = ht;
    return f;
  }
  double per_mm_x() const { return (wx1 - wx0) / (vx1 - vx0); }
  double per_mm_y() const { return (wy1 - wy0) / (vy1 - vy0); }
  // world coordinates of a point given as fractions of the viewport
  double x_at(double fx) const { return wx0 + fx * (wx1 - wx0); }
  double y_at(double fy) const { return wy0 + fy * (wy1 - wy0); }
};

// A marker drawn as polygons and strokes (never a font glyph), centred on (x, y), in the current colour.
// Symbol codes as PLplot's: 2 plus, 3 asterisk, 4 circle, 5 cross, 17 dot; any other a filled square.
void draw_marker(plstream& pls, const Frame& fr, int code, double scale, double x, double y) {
  const double ax = fr.per_mm_x(), ay = fr.per_mm_y();
  const double r = (code == 17 ? 0.45 : 1.5) * scale;  // mm
  auto stroke = [&](double x0, double y0, double x1, double y1) {
    PLFLT xs[2] = {x + x0 * ax, x + x1 * ax}, ys[2] = {y + y0 * ay, y + y1 * ay};
    pls.line(2, xs, ys);
  };
  pls.width(std::max(1.0, 0.9 * scale));
  pls.lsty(1);
  switch (code) {
    case 2:
      stroke(-r, 0, r, 0), stroke(0, -r, 0, r);
      break;
    case 3:
      stroke(-r, 0, r, 0), stroke(0, -r, 0, r);
      stroke(-0.7 * r, -0.7 * r, 0.7 * r, 0.7 * r), stroke(-0.7 * r, 0.7 * r, 0.7 * r, -0.7 * r);
      break;
    case 5:
      stroke(-0.8 * r, -0.8 * r, 0.8 * r, 0.8 * r), stroke(-0.8 * r, 0.8 * r, 0.8 * r, -0.8 * r);
      break;
    case 4:
    case 17: {
      constexpr int n = 24;
      PLFLT xs[n + 1], ys[n + 1];
      for (int i = 0; i <= n; ++i) {
        const double a = 2 * 3.14159265358979323846 * i / n;
        xs[i] = x + r * std::cos(a) * ax;
        ys[i] = y + r * std::sin(a) * ay;
      }
      if (code == 4) {
        pls.line(n + 1, xs, ys);
      } else {
        pls.psty(0);
        pls.fill(n, xs, ys);
      }
      break;
    }
    default: {
      PLFLT xs[4] = {x - 0.7 * r * ax, x + 0.7 * r * ax, x + 0.7 * r * ax, x - 0.7 * r * ax};
      PLFLT ys[4] = {y - 0.7 * r * ay, y - 0.7 * r * ay, y + 0.7 * r * ay, y + 0.7 * r * ay};
      pls.psty(0);
      pls.fill(4, xs, ys);
    }
  }
}

void draw_panel(plstream& pls, const Panel& p, int page_cols, int page_rows) {
  Extent e;
  if (p.map) {
    e.add(p.map->x0, p.map->y0);
    e.add(p.map->x1, p.map->y1);
  }
  for (const auto& s : p.series)
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) e.add(s.x[i], s.y[i]);
  for (double h : p.hlines) e.add(std::isfinite(e.x0) ? e.x0 : 0.0, h);
  if (!std::isfinite(e.x0)) e = Extent{0, 1, 0, 1};
  double dx = e.x1 - e.x0, dy = e.y1 - e.y0;
  if (!(dx > 0)) dx = std::max(1e-9, std::abs(e.x0) * 0.1 + 1e-9);
  if (!(dy > 0)) dy = std::max(1e-9, std::abs(e.y0) * 0.1 + 1e-9);
  double m = p.map ? 0.0 : 0.04;
  double xmin = p.xmin.value_or(e.x0 - m * dx), xmax = p.xmax.value_or(e.x1 + m * dx);
  double ymin = p.ymin.value_or(e.y0 - m * dy), ymax = p.ymax.value_or(e.y1 + m * dy);
  if (xmax <= xmin) xmax = xmin + 1;
  if (ymax <= ymin) ymax = ymin + 1;

  pls.col0(1);
  pls.adv(0);
  pls.vsta();
  if (p.equal_aspect)
    pls.wind(xmin, xmax, ymin, ymax), pls.vpas(0.15, 0.95, 0.12, 0.9, (ymax - ymin) / (xmax - xmin));
  pls.wind(xmin, xmax, ymin, ymax);

  std::string band_note;  // the colour scale, said in the title (dark = low, light = high)
  if (p.map && p.map->nx >= 2 && p.map->ny >= 2) {
    const Map& mp = *p.map;
    std::vector<double> col(static_cast<size_t>(mp.nx) * mp.ny);
    std::vector<const PLFLT*> rows(static_cast<size_t>(mp.nx));
    double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
    auto tr = [&](double v) { return mp.log_scale ? (v > 0 ? std::log10(v) : std::numeric_limits<double>::quiet_NaN()) : v; };
    for (int iy = 0; iy < mp.ny; ++iy)
      for (int ix = 0; ix < mp.nx; ++ix) {
        double v = tr(mp.z[static_cast<size_t>(iy) * mp.nx + ix]);
        col[static_cast<size_t>(ix) * mp.ny + iy] = v;  // PLplot wants a[ix][iy]
        if (std::isfinite(v)) {
          zmin = std::min(zmin, v);
          zmax = std::max(zmax, v);
        }
      }
    if (std::isfinite(zmin)) {
      if (zmax <= zmin) zmax = zmin + 1e-12;
      // undefined cells get a value above every band so they stay blank
      for (auto& v : col)
        if (!std::isfinite(v)) v = zmax + 10 * (zmax - zmin);
      for (int ix = 0; ix < mp.nx; ++ix) rows[static_cast<size_t>(ix)] = col.data() + static_cast<size_t>(ix) * mp.ny;
      int nl = std::max(2, mp.levels + 1);
      std::vector<PLFLT> lev(static_cast<size_t>(nl));
      for (int i = 0; i < nl; ++i) lev[static_cast<size_t>(i)] = zmin + (zmax - zmin) * i / (nl - 1);
      pls.scmap1n(256);
      PLFLT pos[] = {0.0, 0.5, 1.0}, r[] = {0.27, 0.13, 0.99}, g[] = {0.0, 0.57, 0.91}, b[] = {0.33, 0.55, 0.14};
      pls.scmap1l(true, 3, pos, r, g, b, nullptr);  // viridis-like: purple, teal, yellow
      pls.shades(rows.data(), mp.nx, mp.ny, nullptr, mp.x0, mp.x1, mp.y0, mp.y1, lev.data(), nl, 1.0, 0, 0.0,
                 plcallback::fill, true, nullptr, nullptr);
      // contour lines over the bands
      std::vector<PLFLT> xg(static_cast<size_t>(mp.nx)), yg(static_cast<size_t>(mp.ny));
      for (int i = 0; i < mp.nx; ++i) xg[static_cast<size_t>(i)] = mp.x0 + (mp.x1 - mp.x0) * i / (mp.nx - 1);
      for (int i = 0; i < mp.ny; ++i) yg[static_cast<size_t>(i)] = mp.y0 + (mp.y1 - mp.y0) * i / (mp.ny - 1);
      PLcGrid cg{xg.data(), yg.data(), nullptr, mp.nx, mp.ny, 0};
      char note[160];
      auto shown = [&](double v) { return mp.log_scale ? std::pow(10.0, v) : v; };
      std::snprintf(note, sizeof note, "(dark %.4g to light %.4g%s%s%s)", shown(zmin), shown(zmax),
                    mp.colorbar_label.empty() ? "" : " ", mp.colorbar_label.c_str(), mp.log_scale ? ", log bands" : "");
      band_note = note;
      pls.col0(2);
      pls.width(0.6);
      pls.cont(rows.data(), mp.nx, mp.ny, 1, mp.nx, 1, mp.ny, lev.data(), nl, plcallback::tr1, &cg);
    }
  }

  for (const Isoline& iso : p.isolines) {
    const Map& f = iso.field;
    if (f.nx < 2 || f.ny < 2 || f.z.size() != static_cast<size_t>(f.nx) * f.ny) continue;
    std::vector<double> col(static_cast<size_t>(f.nx) * f.ny);
    std::vector<const PLFLT*> rows(static_cast<size_t>(f.nx));
    bool any_below = false, any_above = false;
    for (int iy = 0; iy < f.ny; ++iy)
      for (int ix = 0; ix < f.nx; ++ix) {
        const double v = f.z[static_cast<size_t>(iy) * f.nx + ix];
        // undefined cells lie beyond the line (so that it closes around the defined part)
        const double w = std::isfinite(v) ? v : iso.level + 1e30;
        col[static_cast<size_t>(ix) * f.ny + iy] = w;
        (w < iso.level ? any_below : any_above) = true;
      }
    if (!any_below || !any_above) continue;
    for (int ix = 0; ix < f.nx; ++ix) rows[static_cast<size_t>(ix)] = col.data() + static_cast<size_t>(ix) * f.ny;
    std::vector<PLFLT> xg(static_cast<size_t>(f.nx)), yg(static_cast<size_t>(f.ny));
    for (int i = 0; i < f.nx; ++i) xg[static_cast<size_t>(i)] = f.x0 + (f.x1 - f.x0) * i / (f.nx - 1);
    for (int i = 0; i < f.ny; ++i) yg[static_cast<size_t>(i)] = f.y0 + (f.y1 - f.y0) * i / (f.ny - 1);
    PLcGrid cg{xg.data(), yg.data(), nullptr, f.nx, f.ny, 0};
    PLFLT lev[1] = {iso.level};
    const int ci = kIsolineColor + static_cast<int>(&iso - p.isolines.data()) % (kSeriesColor - kIsolineColor);
    pls.scol0(ci, iso.color.r, iso.color.g, iso.color.b);
    pls.col0(ci);
    pls.width(iso.width);
    pls.cont(rows.data(), f.nx, f.ny, 1, f.nx, 1, f.ny, lev, 1, plcallback::tr1, &cg);
  }

  pls.col0(1);
  pls.width(1.0);
  pls.syax(6, 0);  // enough digits for the tick labels of a narrow range far from zero (-1.0725)
  pls.box("bcnst", 0.0, 0, "bcnstv", 0.0, 0);
  std::string title = p.title;
  if (!band_note.empty()) title += "  " + band_note;
  pls.lab(p.xlabel.c_str(), "", "");
  const Frame fr = Frame::of(pls, page_cols, page_rows);
  {
    // The title, centred over the plot, must stay on its subpage: a title wider than the room there (about 0.75
    // character heights a character in the sans-serif font) is drawn smaller, not clipped.
    PLFLT sx0, sx1, sy0, sy1;
    pls.gspa(sx0, sx1, sy0, sy1);
    const double sub_w = sx1 - sx0;
    const double left = std::fmod(fr.vx0, sub_w), right = sub_w - std::fmod(fr.vx1, sub_w);
    const double room = (fr.vx1 - fr.vx0) + 2.0 * std::max(0.0, std::min(left, right));
    const double wide = 0.75 * fr.ch * static_cast<double>(title.size());
    const double k = std::min(1.0, 0.95 * room / std::max(wide, 1e-9));
    pls.schr(0.0, 0.85 * k);
    pls.mtex("t", 1.6, 0.5, 0.5, title.c_str());
    pls.schr(0.0, 0.85);
  }
  // clear of tick labels up to seven characters long; an equal-aspect panel (maps, contours: short tick labels)
  // may have little room left of its viewport, so its label sits closer
  pls.mtex("l", p.equal_aspect ? 5.0 : 7.0, 0.5, 0.5, p.ylabel.c_str());
  for (double h : p.hlines) {
    PLFLT x[2] = {xmin, xmax}, y[2] = {h, h};
    pls.col0(2);
    pls.lsty(2);
    pls.line(2, x, y);
    pls.lsty(1);
  }
  std::vector<std::string> texts;
  std::vector<PLINT> opts, lcol, lsty;
  std::vector<PLFLT> lw;
  int color_index = kSeriesColor;
  std::vector<const Series*> marked;  // legend entries with a marker, drawn after the legend's box
  for (const auto& s : p.series) {
    size_t n = std::min(s.x.size(), s.y.size());
    pls.scol0(color_index, s.color.r, s.color.g, s.color.b);
    pls.col0(color_index);
    if (s.width > 0 && n >= 2) {
      pls.width(s.width);
      pls.lsty(s.dashed ? 2 : 1);
      pls.line(static_cast<PLINT>(n), s.x.data(), s.y.data());
      pls.lsty(1);
    }
    if (s.marker != 0 && n > 0) {
      for (size_t i = 0; i < n; ++i)
        if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]) && s.x[i] >= std::min(fr.wx0, fr.wx1) &&
            s.x[i] <= std::max(fr.wx0, fr.wx1) && s.y[i] >= std::min(fr.wy0, fr.wy1) && s.y[i] <= std::max(fr.wy0, fr.wy1))
          draw_marker(pls, fr, s.marker, s.marker_scale, s.x[i], s.y[i]);
      pls.width(1.0);
    }
    if (!s.label.empty()) {
      texts.push_back(s.label);
      marked.push_back(s.marker != 0 ? &s : nullptr);
      opts.push_back(s.width > 0 ? PL_LEGEND_LINE : PL_LEGEND_NONE);
      lcol.push_back(color_index);
      lsty.push_back(s.dashed ? 2 : 1);
      lw.push_back(s.width);
    }
    // PLplot legends refer to cmap0 indices; each series keeps its colour in its own index
    color_index = std::min(color_index + 1, kColors - 1);
  }
  if (!texts.empty()) {
    std::vector<const char*> tp;
    for (auto& t : texts) tp.push_back(t.c_str());
    std::vector<PLINT> tcol(texts.size(), 1);
    PLFLT lwid, lhei;
    PLINT pos = PL_POSITION_INSIDE;
    switch (p.legend) {
      case Panel::Legend::top_right: pos |= PL_POSITION_TOP | PL_POSITION_RIGHT; break;
      case Panel::Legend::top_left: pos |= PL_POSITION_TOP | PL_POSITION_LEFT; break;
      case Panel::Legend::bottom_right: pos |= PL_POSITION_BOTTOM | PL_POSITION_RIGHT; break;
      case Panel::Legend::bottom_left: pos |= PL_POSITION_BOTTOM | PL_POSITION_LEFT; break;
    }
    constexpr double kX = 0.02, kY = 0.02, kSwatch = 0.08;  // offsets and swatch width, fractions of the viewport
    pls.legend(&lwid, &lhei, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX, pos, kX, kY, kSwatch, 0, 1, 1, 0, 0,
               static_cast<PLINT>(texts.size()), opts.data(), 1.0, 0.8, 2.0, 0.0, tcol.data(), tp.data(), nullptr,
               nullptr, nullptr, nullptr, lcol.data(), lsty.data(), lw.data(), nullptr, nullptr, nullptr, nullptr);
    // The markers, as in the plot, at the centre of each entry's swatch: PLplot lays the legend out from its top
    // left corner, rows of equal height, the swatch after a border of 0.4 character heights.
    const bool right = p.legend == Panel::Legend::top_right || p.legend == Panel::Legend::bottom_right;
    const bool top = p.legend == Panel::Legend::top_right || p.legend == Panel::Legend::top_left;
    const double left_f = right ? 1.0 - kX - lwid : kX, top_f = top ? 1.0 - kY : kY + lhei;
    const double border_f = 0.4 * fr.ch / (fr.vx1 - fr.vx0);
    const double xm = fr.x_at(left_f + border_f + 0.5 * kSwatch);
    for (size_t i = 0; i < marked.size(); ++i) {
      if (!marked[i]) continue;
      const double ym = fr.y_at(top_f - (static_cast<double>(i) + 0.5) * lhei / static_cast<double>(marked.size()));
      pls.col0(lcol[i]);
      draw_marker(pls, fr, marked[i]->marker, std::min(marked[i]->marker_scale, 2.0), xm, ym);
    }
  }
  pls.width(1.0);
}

}  // namespace

std::string render(const Figure& f, const std::string& format) {
  if (format != "png" && format != "svg") throw InputError("plots are written as .png or .svg, not ." + format);
  std::lock_guard<std::mutex> lock(plplot_mutex());
  const TempFile temp("/tmp/polarcam-plot-" + std::to_string(::getpid()) + "." + format);
  const std::string& tmp = temp.path();
  {
    plstream pls;
    pls.sdev(format == "png" ? "pngcairo" : "svgcairo");
    pls.sfnam(tmp.c_str());
    pls.spage(0, 0, f.width, f.height, 0, 0);
    pls.scmap0n(kColors);
    pls.scol0(0, 255, 255, 255);
    pls.scol0(1, 0, 0, 0);
    pls.scol0(2, 140, 140, 140);
    pls.ssub(std::max(1, f.cols), std::max(1, f.rows));
    pls.init();
    pls.schr(0.0, 0.85);
    for (const auto& p : f.panels) draw_panel(pls, p, f.cols, f.rows);
  }  // the stream's destructor finishes the file
  std::ifstream in(tmp, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  if (bytes.empty()) throw InputError("the plot could not be rendered");
  return bytes;
}

std::string plot_format(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext != ".png" && ext != ".svg")
    throw InputError("plots are written as .png or .svg files, not " + (ext.empty() ? std::string("without one") : ext),
                     path);
  return ext.substr(1);
}

void check_plot_path(const std::string& path) {
  (void)plot_format(path);
  check_output_path(path);
}

void save(const Figure& f, const std::string& path) { cli::write_file_atomic(path, render(f, plot_format(path))); }

}  // namespace polarcam::plot
