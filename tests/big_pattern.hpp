#pragma once
// Large theta-rho patterns made on the fly (never checked in), of the kind public sand-table collections hold:
// a spiral of 1000 vertices a turn whose rho runs from the rim to the centre and back five times (a triangle wave
// in the vertex index), the arm turning half a turn at the centre at each of the five troughs. Theta is
// cumulative and ends past 600 rad for 10^5 vertices. Used by the tests and by bench/bench_pattern.cpp.
#include <cmath>
#include <cstddef>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace polarcam::test {

struct PatternVertex {
  double theta, rho;  // rad (cumulative), 0..1
};

// n vertices (n >= 10); rho is exactly 0 at the troughs, where two vertices (before and after the arm's half
// turn) lie at the centre.
inline std::vector<PatternVertex> big_spiral_pattern(size_t n) {
  const size_t period = n / 5;
  const double dth = 2 * std::numbers::pi / 1000;
  std::vector<PatternVertex> v;
  v.reserve(n + 1);
  double off = 0.0;
  for (size_t i = 0; v.size() < n; ++i) {
    const size_t k = i % period;
    const double rho = std::abs(2.0 * static_cast<double>(k) / static_cast<double>(period) - 1.0);
    const double th = static_cast<double>(i) * dth + off;
    v.push_back({th, rho});
    if (k == period / 2) {  // rho = 0 exactly here: half a turn of the arm at the centre
      off += std::numbers::pi;
      v.push_back({th + std::numbers::pi, 0.0});
    }
  }
  v.resize(n);
  return v;
}

// The pattern as the text of a .thr file (every number written so that it reads back to the same double).
inline std::string thr_text(const std::vector<PatternVertex>& v) {
  std::ostringstream os;
  os.precision(17);
  os << "# generated: " << v.size() << " vertices\n";
  for (const PatternVertex& p : v) os << p.theta << ' ' << p.rho << '\n';
  return os.str();
}

}  // namespace polarcam::test
