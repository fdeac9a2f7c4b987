// Template images traced into contours (cam/image_trace): images made here pixel by pixel from known shapes, in
// every format the reader takes (PGM, PBM plain and raw, PNG written by libpng directly), traced and measured
// against the shapes' own radii and centres.
#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "cam/error.hpp"
#include "cam/image_trace.hpp"
#include "cam/svg_import.hpp"

namespace tu_cam_test_image_trace {  // the test files of a program compile together (unity build)

using namespace polarcam;

namespace {

// A W x H image, pixel (column i, row j from the top) black when `ink` says so of its centre in y-up pixel units.
GrayImage draw(int w, int h, const std::function<bool(double x, double y)>& ink) {
  GrayImage im;
  im.width = w;
  im.height = h;
  im.luminance.assign(static_cast<size_t>(w) * h, 255);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      if (ink(i + 0.5, h - j - 0.5)) im.luminance[static_cast<size_t>(j) * w + i] = 0;
  return im;
}

std::string pgm_raw(const GrayImage& im) {
  std::string s = "P5\n# made by the test\n" + std::to_string(im.width) + " " + std::to_string(im.height) + "\n255\n";
  s.append(im.luminance.begin(), im.luminance.end());
  return s;
}

// Distances of the curve's points (1000 samples per unit of its parameter) from c, in pixels.
void radius_range(const Curve& curve, Vec2 c, double px, double& lo, double& hi) {
  lo = 1e300;
  hi = 0;
  const double a = curve.u_begin(), b = curve.u_end();
  const int n = static_cast<int>(1000 * (b - a));
  for (int k = 0; k <= n; ++k) {
    const Vec2 p = curve.eval(a + (b - a) * k / n, 0).p;
    const double d = std::hypot(p.x - c.x, p.y - c.y) / px;
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
}

std::string write_temp(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// A PNG written with libpng's simplified API (independent of the reader's decoding): 8-bit RGBA or gray.
std::string write_png(const std::string& name, int w, int h, const std::vector<uint8_t>& pixels, bool rgba) {
  const std::string path = ::testing::TempDir() + name;
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(w);
  image.height = static_cast<png_uint_32>(h);
  image.format = rgba ? PNG_FORMAT_RGBA : PNG_FORMAT_GRAY;
  EXPECT_TRUE(png_image_write_to_file(&image, path.c_str(), 0, pixels.data(), 0, nullptr)) << image.message;
  return path;
}

}  // namespace

TEST(ImageTrace, DiskComesBackWithinOnePixelOfItsRadiusAndCentre) {
  const double R = 150.3, cx = 201.7, cy = 180.2, px = 1e-4;  // pixels; 0.1 mm pixels
  // written as a raw PGM file and read back
  const GrayImage im = read_image(write_temp("disk.pgm", pgm_raw(draw(400, 360, [&](double x, double y) { return std::hypot(x - cx, y - cy) <= R; }))));
  TraceOptions o;
  o.pixel_size_m = px;
  const Tracing t = trace_image(im, o, "disk.pgm");
  ASSERT_EQ(t.contours.size(), 1u);
  EXPECT_FALSE(t.contours[0].hole);
  EXPECT_TRUE(t.contours[0].curve->closed());
  // the mean radius (the arc length over 2 pi) within a pixel; every point within a pixel and a half (the pixels'
  // staircase lies up to a half-diagonal either side of the circle)
  EXPECT_NEAR(arc_length(*t.contours[0].curve, t.contours[0].curve->u_begin(), t.contours[0].curve->u_end()) / (2 * std::numbers::pi) / px, R, 1.0);
  double lo, hi;
  radius_range(*t.contours[0].curve, {cx * px, cy * px}, px, lo, hi);
  EXPECT_GT(lo, R - 1.5);
  EXPECT_LT(hi, R + 1.5);
  std::printf("disk of radius %.2f px traced: %.3f .. %.3f px from its centre\n", R, lo, hi);
  // the centre: the box of the traced outline, centred within a pixel
  const Box b = bounding_box(*t.contours[0].curve);
  EXPECT_NEAR(0.5 * (b.lo.x + b.hi.x) / px, cx, 1.0);
  EXPECT_NEAR(0.5 * (b.lo.y + b.hi.y) / px, cy, 1.0);
  EXPECT_DOUBLE_EQ(t.width_m(), 400 * px);
  EXPECT_DOUBLE_EQ(t.height_m(), 360 * px);
}

TEST(ImageTrace, RingGivesItsOutlineAndItsHole) {
  const double R1 = 120, R0 = 70, c = 150;
  const GrayImage im = draw(300, 300, [&](double x, double y) {
    const double d = std::hypot(x - c, y - c);
    return d <= R1 && d >= R0;
  });
  TraceOptions o;
  o.pixel_size_m = 2e-4;
  const Tracing t = trace_image(im, o, "ring.pgm");
  ASSERT_EQ(t.contours.size(), 2u);
  int holes = 0;
  for (const TracedContour& k : t.contours) {
    double lo, hi;
    radius_range(*k.curve, {c * 2e-4, c * 2e-4}, 2e-4, lo, hi);
    const double R = k.hole ? R0 : R1;
    EXPECT_NEAR(arc_length(*k.curve, k.curve->u_begin(), k.curve->u_end()) / (2 * std::numbers::pi) / 2e-4, R, 1.0) << (k.hole ? "hole" : "outline");
    EXPECT_GT(lo, R - 1.5) << (k.hole ? "hole" : "outline");
    EXPECT_LT(hi, R + 1.5) << (k.hole ? "hole" : "outline");
    holes += k.hole;
  }
  EXPECT_EQ(holes, 1);
}

TEST(ImageTrace, YPointsUpAndInvertSwapsInkAndPaper) {
  // a square in the top left corner of a 100 x 100 image: its traced y is near the top
  const GrayImage im = draw(100, 100, [](double x, double y) { return x < 30 && y > 70; });
  TraceOptions o;
  o.pixel_size_m = 1e-3;
  const Tracing t = trace_image(im, o, "corner.pgm");
  ASSERT_EQ(t.contours.size(), 1u);
  const Box b = bounding_box(*t.contours[0].curve);
  EXPECT_NEAR(b.lo.x, 0.0, 1e-9);
  EXPECT_NEAR(b.hi.x, 0.030, 1e-9);
  EXPECT_NEAR(b.lo.y, 0.070, 1e-9);
  EXPECT_NEAR(b.hi.y, 0.100, 1e-9);
  // inverted, the paper is the ink: the image's whole frame with the square as a hole
  o.invert = true;
  const Tracing inv = trace_image(im, o, "corner.pgm");
  ASSERT_EQ(inv.contours.size(), 1u);  // the paper's outline touches the square: one boundary, the L shape's
  const Box bi = bounding_box(*inv.contours[0].curve);
  EXPECT_NEAR(bi.hi.x, 0.100, 1e-9);
  EXPECT_NEAR(bi.lo.y, 0.0, 1e-9);
}

TEST(ImageTrace, ThresholdAndDespeckle) {
  // a mid-gray disk: ink below a threshold of 0.6, paper below 0.4
  GrayImage im = draw(80, 80, [](double x, double y) { return std::hypot(x - 40, y - 40) < 25; });
  for (uint8_t& l : im.luminance)
    if (l == 0) l = 128;
  // and a speck of 2 pixels
  im.luminance[5 * 80 + 5] = im.luminance[5 * 80 + 6] = 0;
  TraceOptions o;
  o.pixel_size_m = 1e-4;
  o.threshold = 0.6;
  EXPECT_EQ(trace_image(im, o, "gray.pgm").contours.size(), 1u);  // the speck is despeckled (2 pixels)
  o.despeckle = 0;
  EXPECT_EQ(trace_image(im, o, "gray.pgm").contours.size(), 2u);
  o.threshold = 0.4;
  EXPECT_EQ(trace_image(im, o, "gray.pgm").contours.size(), 1u);  // the speck alone
}

TEST(ImageTrace, ReadsEveryNetpbmFormat) {
  // the same 5 x 3 picture: an L of ink
  const char* rows[] = {"10000", "10000", "11100"};
  std::string p1 = "P1\n# an L\n5 3\n", p2 = "P2\n5 3\n15\n";
  std::string p4 = "P4 5 3\n", p5_16 = "P5 5 3 65535\n";
  for (const char* r : rows) {
    uint8_t byte = 0;
    for (int i = 0; i < 5; ++i) {
      const bool ink = r[i] == '1';
      p1 += ink ? "1" : "0";
      p2 += ink ? "0 " : "15 ";
      byte |= static_cast<uint8_t>(ink) << (7 - i);
      p5_16 += ink ? std::string("\0\0", 2) : std::string("\xff\xff", 2);
    }
    p1 += "\n";
    p4 += static_cast<char>(byte);
  }
  for (const std::string& bytes : {p1, p2, p4, p5_16}) {
    const GrayImage im = parse_image(bytes, "l.pnm");
    ASSERT_EQ(im.width, 5);
    ASSERT_EQ(im.height, 3);
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 5; ++i)
        EXPECT_EQ(im.luminance[j * 5 + i], rows[j][i] == '1' ? 0 : 255) << bytes.substr(0, 2) << " " << i << "," << j;
    EXPECT_FALSE(im.pixel_size_m.has_value());
  }
}

TEST(ImageTrace, ReadsPngWithItsResolutionAndTransparencyAsPaper) {
  // RGBA: a red disk on transparent background; half-transparent black pixels in a corner count as gray
  const int w = 60, h = 40;
  std::vector<uint8_t> px(static_cast<size_t>(w) * h * 4, 0);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      uint8_t* p = &px[(static_cast<size_t>(j) * w + i) * 4];
      if (std::hypot(i + 0.5 - 30, j + 0.5 - 20) < 15) p[0] = 255, p[3] = 255;  // opaque red: luminance 0.21
    }
  const GrayImage im = read_image(write_png("disk.png", w, h, px, true));
  ASSERT_EQ(im.width, w);
  ASSERT_EQ(im.height, h);
  EXPECT_EQ(im.luminance[0], 255);                  // transparent: white paper
  const int red = im.luminance[20 * w + 30];
  // BT.709 luminance of pure red in linear light, 0.2126, sRGB-encoded as a gray level
  EXPECT_NEAR(red, 255 * (1.055 * std::pow(0.2126, 1 / 2.4) - 0.055), 2);
  TraceOptions o;
  EXPECT_THROW(trace_image(im, o, "disk.png"), InputError);  // no pHYs and no --pixel-size
  o.pixel_size_m = 1e-4;
  EXPECT_EQ(trace_image(im, o, "disk.png").contours.size(), 1u);
}

TEST(ImageTrace, PngResolutionGivesThePixelSize) {
  // a PNG with pHYs of 11811 pixels per metre (300 dpi), written with libpng's full API
  const std::string path = ::testing::TempDir() + "dpi.png";
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_TRUE(f);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  ASSERT_FALSE(setjmp(png_jmpbuf(png)));
  png_init_io(png, f);
  png_set_IHDR(png, info, 8, 8, 8, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_pHYs(png, info, 11811, 11811, PNG_RESOLUTION_METER);
  png_write_info(png, info);
  uint8_t row[8];
  for (int j = 0; j < 8; ++j) {
    for (int i = 0; i < 8; ++i) row[i] = (i >= 2 && i < 6 && j >= 2 && j < 6) ? 0 : 255;
    png_write_row(png, row);
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
  const GrayImage im = read_image(path);
  ASSERT_TRUE(im.pixel_size_m.has_value());
  EXPECT_DOUBLE_EQ(*im.pixel_size_m, 1.0 / 11811);
  const Tracing t = trace_image(im, TraceOptions{}, path);
  ASSERT_EQ(t.contours.size(), 1u);
  const Box b = bounding_box(*t.contours[0].curve);
  EXPECT_NEAR(b.width(), 4.0 / 11811, 1e-12);
}

TEST(ImageTrace, SvgStatesItsSizeInMillimetresAndReadsBackTheSameContours) {
  const GrayImage im = draw(200, 100, [](double x, double y) {
    const double d = std::hypot(x - 100, y - 50);
    return d < 40 && d > 20;
  });
  TraceOptions o;
  o.pixel_size_m = 0.5e-3;  // 100 x 50 mm
  const Tracing t = trace_image(im, o, "ring.pgm");
  const std::string svg = tracing_svg(t, "ring.pgm");
  EXPECT_NE(svg.find("width=\"100mm\" height=\"50mm\" viewBox=\"0 0 100 50\""), std::string::npos) << svg.substr(0, 300);
  EXPECT_EQ(svg, tracing_svg(trace_image(im, o, "ring.pgm"), "ring.pgm"));  // same bytes
  const SvgDrawing d = parse_svg(svg, "ring.svg");
  ASSERT_EQ(d.contours.size(), t.contours.size());
  EXPECT_NEAR(d.width, 0.1, 1e-12);
  EXPECT_NEAR(d.height, 0.05, 1e-12);
  for (size_t k = 0; k < t.contours.size(); ++k) {
    const Box a = bounding_box(*t.contours[k].curve), b = bounding_box(*d.contours[k].curve);
    EXPECT_NEAR(a.lo.x, b.lo.x, 1e-8);
    EXPECT_NEAR(a.lo.y, b.lo.y, 1e-8);
    EXPECT_NEAR(a.hi.x, b.hi.x, 1e-8);
    EXPECT_NEAR(a.hi.y, b.hi.y, 1e-8);
  }
}

TEST(ImageTrace, BadImagesAreOneLineErrors) {
  auto message = [](const std::function<void()>& f) -> std::string {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(message([] { parse_image("", "e.png"); }).find("empty"), std::string::npos);
  EXPECT_NE(message([] { parse_image("GIF89a....", "x.gif"); }).find("PNG, PBM or PGM"), std::string::npos);
  EXPECT_NE(message([] { parse_image("P5 4 4 255\n\x01\x02", "t.pgm"); }).find("ends early"), std::string::npos);
  EXPECT_NE(message([] { parse_image("P2 2 1 10\n3 11", "t.pgm"); }).find("above the image's largest"), std::string::npos);
  EXPECT_NE(message([] { parse_image("P1 0 3\n", "t.pbm"); }).find("empty"), std::string::npos);
  EXPECT_NE(message([] { parse_image("P5 100000 100000 255\n", "t.pgm"); }).find("2^28"), std::string::npos);
  // a PNG cut in the middle
  const int w = 16, h = 16;
  std::vector<uint8_t> px(w * h, 0);
  std::ifstream in(write_png("cut.png", w, h, px, false), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string m = message([&] { parse_image(bytes.substr(0, bytes.size() / 2), "cut.png"); });
  EXPECT_NE(m.find("cut.png"), std::string::npos) << m;
  EXPECT_NE(m.find("PNG"), std::string::npos) << m;
  // all ink, no ink, no pixel size, only specks
  TraceOptions o;
  o.pixel_size_m = 1e-4;
  GrayImage black;
  black.width = black.height = 4;
  black.luminance.assign(16, 0);
  EXPECT_NE(message([&] { trace_image(black, o, "b.pgm"); }).find("all ink"), std::string::npos);
  GrayImage white = black;
  white.luminance.assign(16, 255);
  EXPECT_NE(message([&] { trace_image(white, o, "w.pgm"); }).find("no ink"), std::string::npos);
  GrayImage speck = white;
  speck.luminance[5] = 0;
  EXPECT_NE(message([&] { trace_image(speck, o, "s.pgm"); }).find("despeckle"), std::string::npos);
  o.threshold = 0;
  EXPECT_NE(message([&] { trace_image(speck, o, "s.pgm"); }).find("threshold"), std::string::npos);
}

}  // namespace tu_cam_test_image_trace
