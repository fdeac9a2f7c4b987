// Figures render to PNG and SVG (through PLplot's cairo devices), identically each time.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <vector>

#include <png.h>

#include "report/plot.hpp"
#include "cam/error.hpp"
#include "tests/temp_path.hpp"

using namespace polarcam;

namespace {
plot::Figure sample() {
  plot::Figure f;
  f.width = 1200, f.height = 500, f.cols = 2;
  plot::Panel a;
  a.title = "lines", a.xlabel = "theta (rad)", a.ylabel = "ratio";
  plot::Series s1, s2;
  for (int i = 0; i <= 100; ++i) {
    s1.x.push_back(i * 0.0628);
    s1.y.push_back(std::sin(i * 0.0628));
  }
  s1.label = "sin";
  s2.x = s1.x;
  for (double x : s2.x) s2.y.push_back(0.5 * std::cos(x));
  s2.label = "cos/2";
  s2.color = plot::palette(1);
  s2.dashed = true;
  a.series = {s1, s2};
  a.hlines = {0.8};
  plot::Panel b;
  b.title = "map", b.equal_aspect = true;
  plot::Map m;
  m.nx = 40, m.ny = 30;
  m.x0 = -2, m.x1 = 2, m.y0 = -1.5, m.y1 = 1.5;
  for (int iy = 0; iy < m.ny; ++iy)
    for (int ix = 0; ix < m.nx; ++ix) {
      double x = m.x0 + (m.x1 - m.x0) * ix / (m.nx - 1), y = m.y0 + (m.y1 - m.y0) * iy / (m.ny - 1);
      m.z.push_back(x * x + 2 * y * y < 0.1 ? NAN : x * x + 2 * y * y);
    }
  m.colorbar_label = "mm^2";
  b.map = m;
  plot::Series opt;
  opt.x = {0.5};
  opt.y = {0.2};
  opt.label = "optimum";
  opt.width = 0, opt.marker = 4, opt.marker_scale = 2;
  b.series = {opt};
  f.panels = {a, b};
  return f;
}
}  // namespace

TEST(Plot, RendersPngAndSvgDeterministically) {
  auto f = sample();
  std::string png = plot::render(f, "png"), svg = plot::render(f, "svg");
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_EQ(png, plot::render(f, "png"));
  // (cairo numbers its SVG clip paths per process, so SVG bytes repeat across runs, not within one process)
  EXPECT_THROW(plot::render(f, "gif"), InputError);
  std::string p = polarcam::test::temp_path("plot.png");
  plot::save(f, p);
  if (!std::getenv("POLARCAM_KEEP_PLOT")) std::remove(p.c_str());
}

#include "report/html.hpp"

namespace tu_report_test_plot {  // the test files of a program compile together (unity build)

TEST(Html, ReportIsSelfContained) {
  EXPECT_EQ(html::base64("Man"), "TWFu");
  EXPECT_EQ(html::base64("Ma"), "TWE=");
  EXPECT_EQ(html::base64("M"), "TQ==");
  EXPECT_EQ(html::escape("a<b&\"c\">"), "a&lt;b&amp;&quot;c&quot;&gt;");
  html::Report r("Test <report>");
  r.heading(2, "Section");
  r.table({"a", "b"}, {{"1", "<2>"}});
  r.figure(sample(), "caption", "alt text");
  r.verdict(true, "GO", "all torque ratios below 1");
  std::string s = r.str();
  EXPECT_NE(s.find("data:image/png;base64,iVBOR"), std::string::npos);
  EXPECT_NE(s.find("&lt;2&gt;"), std::string::npos);
  EXPECT_EQ(s.find("<script"), std::string::npos);
  EXPECT_EQ(s.find("src=\"http"), std::string::npos);  // no external resources
  EXPECT_EQ(s.find("href=\"http"), std::string::npos);
}

// ---- pixels: legend colours and titles ------------------------------------------------------------------


namespace {

struct Pixels {
  int w = 0, h = 0;
  std::vector<png_byte> rgb;
  std::array<int, 3> at(int x, int y) const {
    const size_t i = 3 * (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x));
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
  bool white(int x, int y) const { return at(x, y) == std::array<int, 3>{255, 255, 255}; }
};

Pixels decode(const std::string& png) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  Pixels p;
  if (!png_image_begin_read_from_memory(&img, png.data(), png.size())) return p;
  img.format = PNG_FORMAT_RGB;
  p.rgb.resize(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, p.rgb.data(), 0, nullptr)) return {};
  p.w = static_cast<int>(img.width), p.h = static_cast<int>(img.height);
  return p;
}

// Pixels of exactly colour c in rows [y0, y1) of the right half.
int count(const Pixels& p, plot::Color c, int y0, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = p.w / 2; x < p.w; ++x)
      if (p.at(x, y) == std::array<int, 3>{c.r, c.g, c.b}) ++n;
  return n;
}

}  // namespace

TEST(Plot, EveryLegendSwatchHasItsSeriesColour) {
  // Sixteen series, each its own colour, all in the lower left corner of the axes; the legend (top right, one row
  // per series) is the only thing drawn in the right half of the figure in colour. Each legend row must
  // show its series' colour: lines and markers alike, past the 13th series too.
  plot::Figure f = plot::figure(800, 900);
  plot::Panel a = plot::panel("sixteen series", "x", "y");
  a.xmin = 0, a.xmax = 10, a.ymin = 0, a.ymax = 10;
  std::vector<plot::Color> colors;
  for (int i = 0; i < 16; ++i) {
    const plot::Color c{10 + 15 * i, 200 - 11 * i, 37 + 7 * i};
    colors.push_back(c);
    plot::Series s;
    s.label = "series " + std::to_string(i);
    s.color = c;
    if (i % 2 == 0) {  // a line
      s.x = {0.2, 1.0};
      s.y = {0.1 * i, 0.1 * i};
      s.width = 3;
    } else {           // a dot
      s.x = {0.1 * i};
      s.y = {0.5};
      s.width = 0;
      s.marker = 17;
      s.marker_scale = 3;
    }
    a.series.push_back(s);
  }
  f.panels = {a};
  const std::string png = plot::render(f, "png");
  if (std::getenv("POLARCAM_KEEP_PLOT")) std::ofstream(std::getenv("POLARCAM_KEEP_PLOT"), std::ios::binary) << png;
  const Pixels p = decode(png);
  ASSERT_EQ(p.w, 800);
  for (int i = 0; i < 16; ++i) EXPECT_GT(count(p, colors[i], 0, p.h), 4) << "legend row " << i;
}

TEST(Plot, AMarkerInTheLegendIsTheMarkerInThePlot) {
  // One circle marker far from its legend entry: the ink of its colour in the legend (upper half) and in the plot
  // (lower half) must match, the same ring, not a letter "o" of another size.
  plot::Figure f = plot::figure(600, 600);
  plot::Panel a = plot::panel("a marker", "x", "y");
  a.xmin = 0, a.xmax = 10, a.ymin = 0, a.ymax = 10;
  a.series.push_back(plot::marker(2.0, 2.0, "the point", 1, 4, 2.0));
  f.panels = {a};
  const std::string png = plot::render(f, "png");
  if (std::getenv("POLARCAM_KEEP_PLOT")) std::ofstream(std::getenv("POLARCAM_KEEP_PLOT"), std::ios::binary) << png;
  const Pixels p = decode(png);
  ASSERT_EQ(p.w, 600);
  const plot::Color c = plot::palette(1);
  // ink of the colour: coloured pixels (not grey: the text and the axes are black, antialiased to grey) closer to
  // it than to white and to black
  auto ink = [&](int y0, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < p.w; ++x) {
        const auto v = p.at(x, y);
        const int dc = std::abs(v[0] - c.r) + std::abs(v[1] - c.g) + std::abs(v[2] - c.b);
        const int dw = (255 - v[0]) + (255 - v[1]) + (255 - v[2]), dk = v[0] + v[1] + v[2];
        const int spread = std::max({v[0], v[1], v[2]}) - std::min({v[0], v[1], v[2]});
        if (spread > 40 && dc < dw && dc < dk) ++n;
      }
    return n;
  };
  const int legend = ink(0, p.h / 2), plotted = ink(p.h / 2, p.h);
  ASSERT_GT(plotted, 20);
  EXPECT_NEAR(legend, plotted, 0.1 * plotted) << "legend " << legend << ", plot " << plotted;
}

TEST(Plot, TitlesStayOnTheirSubpage) {
  // Two panels side by side with titles longer than a panel is wide: each title is drawn whole, inside the
  // figure (its top row below row 0, nothing on the first or last column) and clear of the other panel.
  plot::Figure f = plot::figure(900, 400);
  f.cols = 2;
  const std::string longer = "A title much longer than the panel is wide, around (-0.64934, 82.674) mm";
  plot::Panel a = plot::panel(longer, "x", "y"), b = plot::panel(longer, "x", "y");
  plot::Series s;
  s.x = {0, 1};
  s.y = {0, 1};
  a.series = {s};
  b.series = {s};
  f.panels = {a, b};
  const Pixels p = decode(plot::render(f, "png"));
  ASSERT_EQ(p.w, 900);
  // the title band: the rows above the first row that is mostly ink (the axes' top edge)
  int band = 0;
  for (int y = 0; y < p.h && band == 0; ++y) {
    int dark = 0;
    for (int x = 0; x < p.w; ++x) dark += p.white(x, y) ? 0 : 1;
    if (dark > p.w / 4) band = y;
  }
  ASSERT_GT(band, 5);
  int top = -1;
  for (int y = 0; y < band && top < 0; ++y)
    for (int x = 0; x < p.w; ++x)
      if (!p.white(x, y)) {
        top = y;
        break;
      }
  ASSERT_GE(top, 0) << "no title drawn";
  EXPECT_GT(top, 0) << "the title's top row is clipped";
  for (int y = 0; y < band; ++y) {
    EXPECT_TRUE(p.white(0, y)) << "row " << y;
    EXPECT_TRUE(p.white(p.w - 1, y)) << "row " << y;
    EXPECT_TRUE(p.white(p.w / 2, y)) << "the titles meet at row " << y;
  }
}

}  // namespace tu_report_test_plot
