#pragma once
// The Cartesian machine's step generators set up for tests: the DDA on line and arc blocks and the exact generator
// on a curve, each recording its steps (tests of machine/cartesian and of the pulse-rate speed in metrics/).
#include <cmath>
#include <numbers>
#include <vector>

#include "cam/path.hpp"
#include "machine/cartesian/cartesian_exact.hpp"
#include "machine/cartesian/dda.hpp"
#include "tests/helpers.hpp"

namespace polarcam::test {

namespace dda {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kBlu = 1e-5;  // 0.01 mm

inline PathSegment line_seg(Vec2 a, Vec2 b) {
  PathSegment s;
  s.from = a;
  s.to = b;
  return s;
}

// A full counter-clockwise circle of radius R BLU about the node c, starting at angle 0, as four quarter arcs.
inline std::vector<PathSegment> circle_segs(double R, Vec2 c = {0, 0}, bool ccw = true) {
  std::vector<PathSegment> segs;
  for (int q = 0; q < 4; ++q) {
    const double a = (ccw ? 1 : -1) * q * kPi / 2;
    segs.push_back(make_arc_segment({(c.x + R * std::cos(a)) * kBlu, (c.y + R * std::sin(a)) * kBlu}, c * kBlu,
                                    ccw ? kPi / 2 : -kPi / 2));
  }
  segs.back().to = segs.front().from;
  return segs;
}

struct Out {
  RecordingSink rec;
  CartesianResult res;
  DdaStats stats;
  DdaProgram prog;
};

inline Out run(const std::vector<PathSegment>& segs, bool closed, double speed, double hz = 5000.0) {
  Out o;
  DdaOptions opt;
  opt.interrupt_hz = hz;
  o.prog = make_dda_program(segs, closed, kBlu, speed, opt);
  o.res = run_dda(o.prog, &o.rec, &o.stats);
  return o;
}

}  // namespace dda

namespace exact {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kBlu = 1e-5;

struct Out {
  RecordingSink rec;
  CartesianResult res;
  CartesianTrack track;
};

inline Out run(const Curve& c, const SpeedProfile* prof_in, double V = 0.02) {
  Out o;
  o.track = CartesianTrack::build(c);
  SpeedProfilePtr prof = make_constant_speed(V, o.track.length());
  o.res = step_exact(o.track, kBlu, prof_in ? *prof_in : *prof, &o.rec);
  return o;
}

}  // namespace exact

}  // namespace polarcam::test
