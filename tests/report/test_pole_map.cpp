// The pole map's CSV: every number with nine significant digits exactly as printf's %.9g writes it, an empty field
// where there is no value, one row per pole position with x fastest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "report/pole_map.hpp"

using namespace polarcam;

namespace {
std::string g9(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}
}  // namespace

TEST(PoleMap, CsvWritesPrintfsNineDigitsAndEmptyFields) {
  ObjectiveMap m;
  m.box = SearchBox{-0.127, 0.0254, 1e-7, 0.1016};
  m.nx = 5;
  m.ny = 4;
  const size_t n = 20;
  // values across the formats %g chooses: fixed and exponent, two- and three-digit exponents, ties, -0, no value
  const std::vector<double> v = {2.8341e-6, 1e-5 / 1e6, 123456789.5 / 1e6, -0.0, NAN, 9.99999999949e-6,
                                 1.0 / 3.0,  1e-300,     1e300,             5e-7, std::numbers::pi * 1e-6,
                                 0.001,      2.5e-10,    1e-4 / 1e6,       4.2e-6, 7e-6, 1e-6, 1.000000005e-6,
                                 NAN,        3e-6};
  m.value = v;
  m.area = v;
  m.margin.resize(n);
  for (size_t i = 0; i < n; ++i) m.margin[i] = (static_cast<double>(i) - 9.5) * 1.234567891234e-3;
  m.margin[7] = INFINITY;
  const std::string csv = map_csv(m, PoleObjective::area);
  std::istringstream in(csv);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "x_mm,y_mm,C_mm,beta_rad,feasible,objective,area_error_mm2,margin_mm");
  for (int iy = 0; iy < m.ny; ++iy)
    for (int ix = 0; ix < m.nx; ++ix) {
      const size_t i = static_cast<size_t>(iy * m.nx + ix);
      const double x = m.box.x0 + (m.box.x1 - m.box.x0) * ix / (m.nx - 1);
      const double y = m.box.y0 + (m.box.y1 - m.box.y0) * iy / (m.ny - 1);
      double beta = std::atan2(y, x);
      if (beta < 0) beta += 2.0 * std::numbers::pi;
      auto field = [](double value, double scale) { return std::isfinite(value) ? g9(value * scale) : std::string(); };
      const std::string want = g9(x * 1e3) + "," + g9(y * 1e3) + "," + g9(std::hypot(x, y) * 1e3) + "," + g9(beta) +
                               "," + (std::isfinite(v[i]) ? "1" : "0") + "," + field(v[i], 1e6) + "," +
                               field(v[i], 1e6) + "," + field(m.margin[i], 1e3);
      ASSERT_TRUE(std::getline(in, line)) << "row " << i;
      EXPECT_EQ(line, want) << "row " << i;
    }
  EXPECT_FALSE(std::getline(in, line)) << "a row too many";
}
