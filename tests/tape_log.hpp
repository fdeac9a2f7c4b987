#pragma once
// A controller's log of executed steps (the in-process emulator's, or the CSV of `polarcam controller-sim` and
// `play --simulate`) against the tape read independently, with no player code.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "digitizer/tape.hpp"
#include "machine/player/int128.hpp"

namespace polarcam::test {

struct LoggedStep {
  uint64_t t_ns;
  int axis, dir;
};

// Step for step the tape's axis and direction, each within one 1 us controller tick of t / K.
inline void expect_log_follows_tape(const std::string& tape, int64_t K, const std::vector<LoggedStep>& log) {
  TapeReader rd(tape);
  const uint64_t tick_ps = rd.header().tick_ps;
  StepRecord r;
  uint64_t t = 0;
  size_t i = 0;
  while (rd.next(r)) {
    t += r.interval;
    ASSERT_LT(i, log.size()) << "the log has only " << log.size() << " steps";
    ASSERT_EQ(log[i].axis, r.axis) << "step " << i + 1;
    ASSERT_EQ(log[i].dir, r.dir) << "step " << i + 1;
    const i128 d = static_cast<i128>(K) * log[i].t_ns * 1000 - static_cast<i128>(t) * tick_ps;
    ASSERT_LE(d < 0 ? -d : d, static_cast<i128>(K) * 1000000) << "step " << i + 1;
    ++i;
  }
  EXPECT_EQ(i, log.size());
}

}  // namespace polarcam::test
