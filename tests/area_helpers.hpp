#pragma once
// Helpers for the area-error tests: digitize a path straight into the area meter.
#include <vector>

#include "cam/toolpath.hpp"
#include "digitizer/digitize.hpp"
#include "tests/helpers.hpp"
#include "metrics/area_error.hpp"

namespace polarcam::test {

struct AreaRun {
  PolarTrack track;
  DigitizeResult dig;
  AreaErrorResult area;
  std::vector<Recorded> steps;
};

inline AreaRun area_run(const Curve& path, const Grid& g, StepRule rule, bool force_general = false) {
  AreaRun r;
  r.track = PolarTrack::build(path);
  auto prof = make_constant_speed(0.01, r.track.length());
  RecordingSink rec;
  r.dig = digitize(r.track, g, rule, *prof, &rec);
  r.steps = rec.steps;
  PolarAreaMeter m;
  m.reset(r.track, g);
  m.set_force_general(force_general);
  for (const auto& s : rec.steps) m.record(s.axis, s.dir);
  r.area = m.finish(r.dig.start_n, r.dig.start_m);
  return r;
}

// Grid nodes of a recorded staircase, start node first.
struct Node {
  long long n, m;
};
inline std::vector<Node> nodes_of(const AreaRun& r) {
  std::vector<Node> v{{r.dig.start_n, r.dig.start_m}};
  for (const auto& s : r.steps) {
    Node x = v.back();
    (s.axis == kAxisRadial ? x.n : x.m) += s.dir;
    v.push_back(x);
  }
  return v;
}

inline Grid coarse_grid(double dr, int64_t steps_per_rev) {
  Grid g;
  g.dr = dr;
  g.steps_per_rev = steps_per_rev;
  g.dtheta = dtheta_from_steps(steps_per_rev);
  return g;
}

}  // namespace polarcam::test
