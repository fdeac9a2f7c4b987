#pragma once
// The controller's step schedule and its exact compression (docs/controller-protocol.md, "Step schedule").
//
// Each axis has its own clock, a 32.32 fixed-point tick count. A run (count n, offset O, interval I, add A, second
// add B; all in 1/2^32 ticks) advances it n times: first by O + I, then by interval_k = I + (k-1) A +
// (k-1)(k-2)/2 B for k = 2..n; the k-th step fires at tick floor(clock). So the k-th step of a run from clock C is
// at C + O + k I + C(k,2) A + C(k,3) B: a cubic in k. A wait advances the clock by whole ticks without stepping.
// The host mirrors this arithmetic bit for bit (RunCursor), so it knows every executed tick in advance; the
// compressor only emits runs whose every step lands in the step's window: within one controller tick of the
// tape's exact scaled time, and in the tape's order across axes.
#include <cstdint>
#include <string>
#include <vector>

#include "machine/link/wire.hpp"
#include "machine/player/play_plan.hpp"

namespace polarcam {

// The items, their validity, the prediction and the arithmetic of a run are the wire's (machine/link/wire.hpp,
// shared with the reference firmware).
using wire::kFracBits;
using wire::kMaxIntervalFx;
using wire::kMaxRunCount;
using wire::kOneTick;
inline constexpr int64_t kMaxSpanTicks = int64_t{1} << 30;    // a run ends less than 2^30 ticks after it starts

using wire::ItemKind;
using wire::QueueItem;
// A run is valid when its first interval (offset + interval) and every later interval lie in [one tick,
// kMaxIntervalFx] and every add A + (k-1) B (k = 1..n) lies within 2^62 in magnitude, so that the controller's
// 64-bit arithmetic never overflows and an axis never steps twice in one tick. The decoder refuses anything else.
using wire::run_is_valid;
// The next run as the wire predicts it: the previous run of the axis continued by one step (interval
// I + n A + C(n,2) B, add A + n B, second add B), in wrapping 64-bit arithmetic. Runs are sent as differences
// from it.
using wire::continuation;
using wire::RunRef;
// The controller's arithmetic of one run and of an axis clock, shared by every party.
using wire::AxisClock;
using wire::RunCursor;

// Executed tick windows of every machine step: |tick * tick_ctrl - t * tick_tape / K| <= one controller tick,
// narrowed so that each axis steps at most once a tick and never at tick 0 (START), and split where two steps of
// different axes are so close that they could otherwise swap order.
struct StepWindow {
  int64_t lo = 0, hi = 0;
};

struct Schedule {
  uint64_t tick_ps = 0;                 // controller tick
  std::vector<QueueItem> items;         // in sending order (each axis's items in its own order)
  std::vector<uint64_t> horizon;        // per item: the axis clock (whole ticks) after it
  std::vector<uint64_t> steps_before;   // per item: machine steps in the items before it (both axes)
  uint64_t steps[2] = {0, 0};
  uint64_t last_tick = 0;               // tick of the last step
  uint64_t runs = 0, waits = 0;
  uint64_t tools = 0;                   // tool items (a lifting tape's: the state at the start, then its events)
  uint64_t tool_dwell_ticks = 0;        // the wait after each tool item, in the steps' ticks
  uint64_t searches = 0;                // run searches (a search whose run the wire's rounding spoils is repeated shorter)
  uint64_t searched_steps = 0;          // steps in the runs the searches proposed: the compressor's work
};

// Windows for every step of the plan at speed scale plan.scaling.speed on a controller of tick `tick_ps`.
// Throws InputError when two steps are closer than the controller can order (speed scale too high for its tick).
// A lifting tape's tool items (plan.tools) act at ticks too: a step's exact time is its scaled tape time plus one
// tool dwell (plan.tool_dwell_s in whole ticks, rounded up) for every tool item before it, and its window keeps it
// on its side of each tool item's tick (tool_ticks()): the steps before an item at or before its tick, those
// after it later.
std::vector<StepWindow> step_windows(const PlayPlan& plan, uint64_t tick_ps);

// The tool dwell in whole controller ticks (rounded up), and the tick of each of plan.tools: its scaled tape time
// plus a dwell for every tool item before it, rounded down.
uint64_t tool_dwell_ticks(const PlayPlan& plan, uint64_t tick_ps);
std::vector<uint64_t> tool_ticks(const PlayPlan& plan, uint64_t tick_ps);

// The runs the compressor may use: cubic runs with a free offset (the default), or the simpler shapes it was
// measured against (docs/benchmarks.md): quadratic (add2 = 0), anchored at the previous run's end (offset = 0).
struct RunShape {
  bool offset = true;
  bool cubic = true;
};

// Compresses the plan into queue items. Throws InputError when a step cannot be placed (an axis would have to
// step twice within one tick).
Schedule compress_schedule(const PlayPlan& plan, uint64_t tick_ps, const RunShape& shape = RunShape{});

// Executes items of one axis and returns the tick of each step (the controller's arithmetic, for tests and the
// simulated machine).
std::vector<uint64_t> execute_axis(const std::vector<QueueItem>& items, int axis);

// Wire encoding of items inside QUEUE messages (wire::ItemCodec, protocol versions 2 and 3): a tag byte (bit 0
// axis, bits 1-2 kind, bit 3 direction +); a run continues with varint count, two bytes of shifts (nibbles s/2
// for the offset, I, A, B), then zigzag varints of the offset and of the differences I, A, B minus the axis's
// prediction (continuation()), each shifted right by its shift; a wait with varint ticks. Encoder and decoder
// keep the same per-axis predictions, so they must see the same items in the same order. encode() needs a
// valid run.
struct ItemCodec : wire::ItemCodec {
  using wire::ItemCodec::decode;
  using wire::ItemCodec::encode;
  void encode(const QueueItem& it, std::string& out) {
    uint8_t b[wire::kMaxItemBytes];
    out.append(reinterpret_cast<const char*>(b), encode(it, b));
  }
};

}  // namespace polarcam
