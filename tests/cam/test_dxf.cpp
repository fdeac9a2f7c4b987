// DXF import: entities in any order and direction chain into one path; bulges become arcs; what cannot be read
// is refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "cam/dxf_import.hpp"
#include "cam/error.hpp"
#include "tests/temp_path.hpp"

using namespace polarcam;

namespace {

std::string line(double x1, double y1, double x2, double y2, const char* layer = "0") {
  std::ostringstream o;
  o << "0\nLINE\n8\n" << layer << "\n10\n" << x1 << "\n20\n" << y1 << "\n30\n0\n11\n" << x2 << "\n21\n" << y2
    << "\n31\n0\n";
  return o.str();
}
std::string dxf(const std::string& entities) { return "0\nSECTION\n2\nENTITIES\n" + entities + "0\nENDSEC\n0\nEOF\n"; }
std::string write(const std::string& name, const std::string& text) {
  std::string p = polarcam::test::temp_path(name);
  std::ofstream(p) << text;
  return p;
}

}  // namespace

TEST(Dxf, ScrambledLinesChainIntoAClosedSquare) {
  // a 40 x 40 mm square whose sides come out of order, two of them drawn backwards
  std::string p = write("sq.dxf", dxf(line(40, 40, 0, 40) + line(0, 0, 40, 0) + line(0, 40, 0, 0) + line(40, 40, 40, 0)));
  DxfPath d = read_dxf_path(p, DxfOptions{});
  ASSERT_EQ(d.segments.size(), 4u);
  EXPECT_TRUE(d.closed);
  double len = 0;
  for (size_t i = 0; i < 4; ++i) {
    len += norm(d.segments[i].to - d.segments[i].from);
    EXPECT_NEAR(norm(d.segments[i].from - d.segments[(i + 3) % 4].to), 0, 1e-15);  // joined end to start
  }
  EXPECT_NEAR(len, 0.16, 1e-15);
  auto c = make_path(d.segments, true);
  EXPECT_NEAR(c->u_end(), 0.16, 1e-15);
  std::remove(p.c_str());
}

TEST(Dxf, BulgesAndArcsAndCircles) {
  // a slot: two straight sides joined by two half circles (bulge 1 = 180 degrees counter-clockwise), radius 5 mm
  std::string poly = "0\nLWPOLYLINE\n8\n0\n90\n4\n70\n1\n10\n0\n20\n0\n42\n0\n10\n20\n20\n0\n42\n1\n10\n20\n20\n10\n42\n0\n10\n0\n20\n10\n42\n1\n";
  std::string p = write("slot.dxf", dxf(poly));
  DxfPath d = read_dxf_path(p, DxfOptions{});
  ASSERT_EQ(d.segments.size(), 4u);
  EXPECT_TRUE(d.closed);
  auto c = make_path(d.segments, true);
  EXPECT_NEAR(c->u_end(), 2 * 0.02 + 2 * std::numbers::pi * 0.005, 1e-14);
  EXPECT_NEAR(std::abs(curvature(c->eval(0.02 + 0.0025, 2))), 200.0, 1e-9);  // on the first half circle
  std::remove(p.c_str());
  // a lone circle and an arc entity (angles in degrees, counter-clockwise)
  std::string q = write("circ.dxf", dxf("0\nCIRCLE\n8\n0\n10\n5\n20\n5\n30\n0\n40\n2.5\n"));
  DxfPath dc = read_dxf_path(q, DxfOptions{});
  ASSERT_EQ(dc.segments.size(), 1u);
  EXPECT_TRUE(dc.closed);
  EXPECT_NEAR(dc.segments[0].sweep, 2 * std::numbers::pi, 1e-15);
  std::string a = write("arc.dxf", dxf("0\nARC\n8\n0\n10\n0\n20\n0\n30\n0\n40\n10\n50\n350\n51\n10\n"));
  DxfPath da = read_dxf_path(a, DxfOptions{0.001, std::nullopt, 1e-6});
  ASSERT_EQ(da.segments.size(), 1u);
  EXPECT_FALSE(da.closed);
  EXPECT_NEAR(da.segments[0].sweep, 20 * std::numbers::pi / 180, 1e-12);  // across 0 degrees
  std::remove(q.c_str());
  std::remove(a.c_str());
}

TEST(Dxf, LayersGapsAndUnsupportedEntities) {
  std::string two = dxf(line(0, 0, 10, 0, "A") + line(10, 0, 10, 10, "A") + line(50, 50, 60, 50, "B"));
  std::string p = write("two.dxf", two);
  EXPECT_THROW(read_dxf_path(p, DxfOptions{}), InputError);  // two separate chains
  DxfOptions layer_a;
  layer_a.layer = "A";
  DxfPath d = read_dxf_path(p, layer_a);
  EXPECT_EQ(d.segments.size(), 2u);
  EXPECT_FALSE(d.closed);
  std::string s = write("spline.dxf", dxf(line(0, 0, 1, 0) + "0\nSPLINE\n8\n0\n70\n8\n71\n3\n72\n0\n73\n0\n"));
  try {
    read_dxf_path(s, DxfOptions{});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("SPLINE"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_dxf_path(polarcam::test::temp_path("missing.dxf"), DxfOptions{}), InputError);
  std::string junk = write("junk.dxf", "hello\nworld\n");
  EXPECT_THROW(read_dxf_path(junk, DxfOptions{}), InputError);
  for (auto& f : {p, s, junk}) std::remove(f.c_str());
}
