#pragma once
// Small helpers shared by the tests.
#include <algorithm>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "cam/toolpath.hpp"
#include "digitizer/digitize.hpp"
#include "tests/temp_path.hpp"

namespace polarcam::test {

struct Recorded {
  int axis, dir;
  int64_t t_ns;
  bool operator==(const Recorded&) const = default;
};
inline std::ostream& operator<<(std::ostream& os, const Recorded& s) {
  return os << "{" << s.axis << ", " << s.dir << ", " << s.t_ns << "}";
}

class RecordingSink : public StepSink {
 public:
  void step(int axis, int dir, int64_t t_ns) override { steps.push_back({axis, dir, t_ns}); }
  std::vector<Recorded> steps;
};

inline Grid thesis_grid(double finer = 1.0) {
  Grid g;
  g.dr = 0.0254e-3 / finer;
  g.steps_per_rev = static_cast<int64_t>(16000 * finer);
  g.dtheta = dtheta_from_steps(g.steps_per_rev);
  return g;
}

struct Run {
  DigitizeResult result;
  std::vector<Recorded> steps;
  PolarTrack track;
};

// Distance from p to the segment from a to b.
inline double dist_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double t = std::clamp(dot(p - a, d) / dot(d, d), 0.0, 1.0);
  return norm(p - (a + t * d));
}

// The largest distance from the outline of the quadrilateral S to that of P, by brute force: 20001 points along each
// edge of S.
inline double outline_deviation(const Vec2 (&S)[4], const Vec2 (&P)[4]) {
  double dmax = 0;
  for (int e = 0; e < 4; ++e)
    for (int k = 0; k <= 20000; ++k) {
      const Vec2 p = S[e] + (k / 20000.0) * (S[(e + 1) % 4] - S[e]);
      double d = 1e300;
      for (int f = 0; f < 4; ++f) d = std::min(d, dist_to_segment(p, P[f], P[(f + 1) % 4]));
      dmax = std::max(dmax, d);
    }
  return dmax;
}

inline Run run_digitizer(const Curve& path, const Grid& g, StepRule rule, double speed) {
  Run r;
  r.track = PolarTrack::build(path);
  auto prof = make_constant_speed(speed, r.track.length());
  RecordingSink sink;
  r.result = digitize(r.track, g, rule, *prof, &sink);
  r.steps = std::move(sink.steps);
  return r;
}

}  // namespace polarcam::test
