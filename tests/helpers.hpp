#pragma once
// Small helpers shared by the tests.
#include <cstdint>
#include <string>
#include <vector>

#include "cam/toolpath.hpp"
#include "digitizer/digitize.hpp"
#include "tests/temp_path.hpp"

namespace polarcam::test {

struct Recorded {
  int axis, dir;
  int64_t t_ns;
};

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
