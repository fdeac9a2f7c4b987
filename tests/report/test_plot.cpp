// Figures render to PNG and SVG (through PLplot's cairo devices), identically each time.
#include <gtest/gtest.h>

#include <cmath>

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
