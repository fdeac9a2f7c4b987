#pragma once
// For the player's and the controller's tests: the examples' tapes, a tape read record by record with no player
// code, and play scalings from their command-line spelling.
#include <cstdint>
#include <string>
#include <vector>

#include "digitizer/tape.hpp"
#include "machine/player/scaling.hpp"
#include "tests/example_tapes.hpp"

namespace polarcam::test {

struct TapeStep {
  int axis, dir;
  uint64_t t;      // tape ticks
  int64_t n, m;    // tape node after the step
};

// The tape read record by record, with no player code.
inline std::vector<TapeStep> read_tape(const std::string& path) {
  TapeReader rd(path);
  std::vector<TapeStep> v;
  StepRecord r;
  uint64_t t = 0;
  int64_t n = rd.header().start[0], m = rd.header().start[1];
  while (rd.next(r)) {
    t += r.interval;
    (r.axis == 0 ? n : m) += r.dir;
    v.push_back({r.axis, r.dir, t, n, m});
  }
  return v;
}

inline PlayScaling scaling(const std::string& speed, const std::string& size = "1", int64_t offset = 0) {
  PlayScaling s;
  s.speed = parse_ratio(speed, "--speed-scale");
  s.size = parse_ratio(size, "--size-scale");
  s.angle_offset = offset;
  return s;
}

}  // namespace polarcam::test
