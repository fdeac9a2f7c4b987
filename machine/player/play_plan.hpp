#pragma once
// The player's first stage: a verified tape turned into the machine's step sequence after size scaling and the
// angular offset, with the work area checked before anything is sent (docs/player.md). Times stay in tape ticks
// here; the speed scale is applied when the steps are given controller-tick times (machine/player/schedule.hpp).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "digitizer/grid.hpp"
#include "digitizer/tape.hpp"
#include "machine/player/scaling.hpp"

namespace polarcam {

struct PlayStep {
  uint64_t t = 0;           // tape ticks from the start of the tape (before the speed scale)
  uint64_t record = 0;      // 1-based tape record this machine step comes from
  uint8_t axis = 0;         // 0 radial, 1 angular
  int8_t dir = 1;           // +1 / -1
};

// The tool lifted or lowered (a tape's tool event, or the tool's state where the play begins).
struct PlayTool {
  uint64_t t = 0;           // tape ticks from the start of the tape (before the speed scale)
  uint64_t before = 0;      // machine steps before it: it comes between steps before - 1 and before (0-based)
  bool down = false;
};

struct PlayPlan {
  std::string tape;                 // path as given
  TapeHeader header;                // verified header of the tape
  PlayScaling scaling;
  int64_t start[2] = {0, 0};        // machine node before the first step
  int64_t end[2] = {0, 0};          // machine node after the last step
  int64_t lo[2] = {0, 0}, hi[2] = {0, 0};  // extreme machine nodes along the way
  uint64_t steps_per_axis[2] = {0, 0};
  std::vector<PlayStep> steps;      // machine steps in execution order
  // A tape that lifts its tool (version 2): first the tool's state where the play begins (t = 0, before = 0), then
  // every tool event in order. Empty for a tape without tool events.
  std::vector<PlayTool> tools;
  // The time the tool needs to go up or down (the machine's tool_dwell): the schedule waits this long after each
  // tool item before the next step; not scaled by the speed scale.
  double tool_dwell_s = 0;
  double tape_tick_s() const { return static_cast<double>(header.tick_ps) * 1e-12; }
};

// The machine a tape is played on: its grid and work area. Without one, the tape's own header is used.
struct PlayMachine {
  std::string source;  // for messages (a machine file, or "the tape's header")
  Grid grid;
};
PlayMachine machine_from_header(const TapeHeader& h);

// Reads and verifies the whole tape, checks that it was made for `machine`'s grid, applies the scaling and
// checks every machine node against the work area. Throws InputError (naming the tape or the option) before
// anything could be sent.
PlayPlan plan_playback(const std::string& tape, const PlayScaling& scaling, const std::optional<PlayMachine>& machine);

// The rest of `plan` after its first `done` machine steps (a run stopped after the controller confirmed them):
// the machine starts at the node those steps reached, and every later step keeps its interval from the step
// before it (the first one from step `done`). A lifting tape's tool starts in the state the events before step
// `done` left it in (the first tool item), and the later events follow. InputError naming --resume when `done`
// is not below the plan's machine steps.
PlayPlan resume_plan(const PlayPlan& plan, uint64_t done);

}  // namespace polarcam
