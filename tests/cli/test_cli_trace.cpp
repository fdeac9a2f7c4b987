// Copy mode from images, end to end: `polarcam trace` and images wherever patterns go. The bundled template
// (examples/templates/cam.png, 300 dpi) is a cam plate whose outline is r = 20 + 6 cos(theta) mm about the image's
// centre with a bore of 5 mm radius and a keyway; the figures below come from that drawing, not from the tracer.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "tests/cli_runner.hpp"

namespace tu_cli_test_cli_trace {  // the test files of a program compile together (unity build)

using namespace polarcam::test;

namespace {

const std::string kSource = POLARCAM_SOURCE_DIR;
const std::string kCam = kSource + "/examples/templates/cam.png";
const std::string kTable = kSource + "/examples/machines/sand-table.toml";
constexpr double kPixel = 1.0 / 11811;  // m: 300 dpi

// A raw PGM of w x h pixels, black where `ink` says so of the pixel's centre (pixel units, y up).
template <class F>
std::string pgm(int w, int h, F ink) {
  std::string s = "P5 " + std::to_string(w) + " " + std::to_string(h) + " 255\n";
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) s += ink(i + 0.5, h - j - 0.5) ? '\0' : '\xff';
  return s;
}

}  // namespace

TEST(Trace, TheBundledTemplateTracesToItsOutlineAndItsHoleAtItsPhysicalSize) {
  Scratch sc;
  const std::string out = sc.path("cam.svg");
  const auto j = cli_json("trace " + kCam + " -o " + out + " --json");
  EXPECT_EQ(j["contours"], 2);
  EXPECT_EQ(j["outlines"], 1);
  EXPECT_EQ(j["holes"], 1);
  EXPECT_EQ(j["pixels"][0], 709);
  EXPECT_DOUBLE_EQ(j["pixel_size_m"].get<double>(), kPixel);
  std::ifstream in(out);
  const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(svg.find("width=\"60.028787mm\" height=\"60.028787mm\""), std::string::npos) << svg.substr(0, 300);
  EXPECT_NE(svg.find("id=\"outline-1\""), std::string::npos);
  EXPECT_NE(svg.find("id=\"hole-1\""), std::string::npos);
  // the text counts them in the singular
  const CliResult text = run_cli("trace " + kCam + " -o " + out);
  EXPECT_NE(text.out.find("2 (1 outline, 1 hole)"), std::string::npos) << text.out;
}

TEST(Trace, AnImageIsAPatternTheTapeSpansTheTemplatesRadiiWithinOnePixel) {
  Scratch sc;
  const auto j = cli_json("digitize " + kCam + " --machine " + kTable + " --speed \"20 mm/s\" -o " +
                          sc.path("cam.tape") + " --json");
  EXPECT_EQ(j["contours"], 2);
  // the image's centre is the pole: the outline reaches 26 mm (theta = 0), the bore comes within 5 mm
  EXPECT_NEAR(j["r_max_path_m"].get<double>(), 0.026, kPixel);
  EXPECT_NEAR(j["r_min_path_m"].get<double>(), 0.005, kPixel);
  // the same image, the same bytes
  cli_json("digitize " + kCam + " --machine " + kTable + " --speed \"20 mm/s\" -o " + sc.path("again.tape") + " --json");
  std::ifstream a(sc.path("cam.tape"), std::ios::binary), b(sc.path("again.tape"), std::ios::binary);
  EXPECT_TRUE(std::equal(std::istreambuf_iterator<char>(a), {}, std::istreambuf_iterator<char>(b)));
  // and it goes to a preview and to G-code like any drawing
  EXPECT_EQ(run_cli("preview " + kCam + " --machine " + kTable + " --speed \"20 mm/s\" -o " + sc.path("p.svg")).code, 0);
  EXPECT_EQ(run_cli("export " + kCam + " --machine " + kTable + " --speed \"20 mm/s\" --format gcode -o " + sc.path("c.ngc")).code, 0);
}

TEST(Trace, ADiskGivesOneExactContourAtThePixelSizeGiven) {
  Scratch sc;
  const double R = 100.4, c = 120.0;  // pixels
  const std::string img = sc.write("disk.pgm", pgm(240, 240, [&](double x, double y) { return std::hypot(x - c, y - c) <= R; }));
  const auto j = cli_json("digitize " + img + " --pixel-size \"0.1 mm\" --machine " + kTable +
                          " --speed \"20 mm/s\" -o " + sc.path("disk.tape") + " --json");
  EXPECT_EQ(j["contours"], 1);
  // its mean radius (the length over 2 pi) within a pixel, every point within a pixel and a half (the staircase of
  // the pixels' edges lies up to a half-diagonal, 0.71 pixel, either side of the circle)
  EXPECT_NEAR(j["path_length_m"].get<double>() / (2 * M_PI), R * 1e-4, 1e-4);
  EXPECT_NEAR(j["r_max_path_m"].get<double>(), R * 1e-4, 1.5e-4);
  EXPECT_NEAR(j["r_min_path_m"].get<double>(), R * 1e-4, 1.5e-4);
}

TEST(Trace, BadImagesAndOptionsAreOneLineErrors) {
  Scratch sc;
  const std::string disk = sc.write("disk.pgm", pgm(50, 50, [](double x, double y) { return std::hypot(x - 25, y - 25) < 10; }));
  const std::string out = sc.path("o.svg");
  expect_refused(run_cli("trace " + disk + " -o " + out), sc, out, "--pixel-size");
  expect_refused(run_cli("trace " + disk + " -o " + out + " --pixel-size \"3 kg\""), sc, out, "--pixel-size");
  expect_refused(run_cli("trace " + disk + " -o " + out + " --pixel-size \"0.1 mm\" --threshold 0"), sc, out, "threshold");
  const std::string black = sc.write("black.pgm", pgm(20, 20, [](double, double) { return true; }));
  expect_refused(run_cli("trace " + black + " -o " + out + " --pixel-size \"0.1 mm\""), sc, out, "all ink");
  const std::string text = sc.write("fake.png", "this is not a picture\n");
  expect_refused(run_cli("trace " + text + " -o " + out), sc, out, "PNG, PBM or PGM");
  const std::string cut = sc.write("cut.pgm", "P5 50 50 255\n\x01\x02\x03");
  expect_refused(run_cli("trace " + cut + " -o " + out + " --pixel-size \"0.1 mm\""), sc, out, "ends early");
  // a missing file is bad input, an output into a missing directory an I/O error
  expect_one_line_error(run_cli("trace " + sc.path("none.png") + " -o " + out), "none.png");
  expect_one_line_error(run_cli("trace " + kCam + " -o " + sc.path("no/dir/o.svg")), "o.svg", 3);
  // the tracing options of an input that is not an image would be ignored: refused, naming the option
  const std::string src = kSource;
  expect_one_line_error(run_cli("digitize " + src + "/examples/circle.toml -o " + sc.path("c.tape") + " --invert"),
                        "--invert: traces a template image (.png, .pbm, .pgm)");
  EXPECT_FALSE(std::filesystem::exists(sc.path("c.tape")));
  expect_one_line_error(run_cli("digitize " + src + "/examples/patterns/logo.svg --machine " + kTable +
                                " --speed \"40 mm/s\" -o " + sc.path("s.tape") + " --threshold 0.9"),
                        "--threshold: traces a template image");
  expect_one_line_error(run_cli("check " + src + "/examples/patterns/star.thr --despeckle 7"), "--despeckle");
  ASSERT_EQ(run_cli("digitize " + src + "/examples/circle.toml -o " + sc.path("x.tape")).code, 0);
  expect_one_line_error(run_cli("error " + sc.path("x.tape") + " --job " + src + "/examples/circle.toml --pixel-size \"1 mm\""),
                        "--pixel-size");
  expect_one_line_error(run_cli("preview " + sc.path("x.tape") + " -o " + sc.path("p.svg") + " --invert"), "--invert");
  // the drawing is SVG: another name is refused, and nothing is written under it
  expect_refused(run_cli("trace " + disk + " -o " + sc.path("o.png") + " --pixel-size \"0.1 mm\""), sc, sc.path("o.png"),
                 "the traced drawing is written as .svg");
  EXPECT_EQ(run_cli("trace " + disk + " -o /dev/null --pixel-size \"0.1 mm\"").code, 0);  // a device takes any name
  // as a pattern: the same messages, naming the image
  expect_one_line_error(run_cli("digitize " + disk + " --machine " + kTable + " --speed \"20 mm/s\" -o " + sc.path("d.tape")),
                        "--pixel-size");
}

}  // namespace tu_cli_test_cli_trace
