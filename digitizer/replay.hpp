#pragma once
// What a machine does with a tape, step by step: the cumulative time of each step and the grid node the axes
// stand on after it. The quasi-static position of the tool; the base of the player, the error metrics and the
// simulator.
#include <cstdint>

#include "digitizer/tape.hpp"

namespace polarcam {

struct MachineStep {
  uint64_t index = 0;   // 1-based step number
  uint64_t t_ticks = 0; // cumulative time of the step
  int axis = 0, dir = 0;
  int64_t node[2] = {0, 0};  // node after the step
};

class TapeReplay {
 public:
  explicit TapeReplay(TapeReader& reader);
  // Next step; false at the end of the tape (after the reader has verified it).
  bool next(MachineStep& s);
  const int64_t* node() const { return node_; }

 private:
  TapeReader& rd_;
  uint64_t index_ = 0, t_ = 0;
  int64_t node_[2];
};

}  // namespace polarcam
