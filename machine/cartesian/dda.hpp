#pragma once
// A conventional NC control's interpolator, as in the NC program of Appendix III of M. A. Elbestawi's thesis
// (McMaster University, 1980; an HP 2100 assembly listing): a fixed-rate interrupt runs a feed accumulator; each time the
// accumulator overflows, the interpolator simulates one cycle of two digital differential analysers (DDAs), and
// every DDA register overflow is one command pulse (one BLU) on its axis. Each block (line or arc within one
// quadrant) carries its end point, its axis counters, a PATH word that is the capacity of its DDA registers,
// and a feed word; the block ends when both axis counters have run down to zero.
//
//  - feed accumulator (listing: FEED): R3 += F at every interrupt; when R3 >= capacity, R3 -= capacity and one
//    DDA cycle runs. Iteration k of a block runs at interrupt ceil(k capacity / F); R3 is cleared at each block.
//  - linear DDA (LINE, DDA2): each cycle, for x then y, R += |delta|; on R >= PATH, R -= PATH and one pulse.
//    PATH = round(length in BLU), so one cycle is one BLU of path and a block takes exactly PATH cycles.
//  - circular DDA (CIRC2, CIRC3, two integrators): within a quadrant one coordinate grows in magnitude (axis a)
//    and the other shrinks (axis b). Each cycle the a-register adds |b| and, on overflow, pulses a and raises
//    |a| by one; then the b-register adds the updated |a| and, on overflow, pulses b and lowers |b| by one. PATH
//    (the register capacity) = round(radius in BLU), so one cycle turns the tool by 1/PATH rad, one BLU of arc.
//
// Decisions of this implementation (docs/cartesian.md): the registers are 64-bit (the listing's are 16-bit);
// the feed accumulator's capacity is 2^16 (the listing's is 3000 with F in 0.01 in/min); the feed word of each
// block is computed so that the block's ideal duration is its length over the programmed speed (which corrects
// the rounding of PATH); end points and arc centres are rounded to the nearest node; once one axis of an arc
// block has run out its count, the other, if it still owes steps (a rounded end point off the DDA's circle),
// takes one every cycle instead of waiting on an integrand that no longer changes (the end-point clean-up).
#include <cstdint>
#include <vector>

#include "cam/path.hpp"
#include "machine/cartesian/cartesian.hpp"

namespace polarcam {

struct DdaOptions {
  double interrupt_hz = 5000.0;     // the listing's interrupt rate (IPF = 5000 pps)
  uint32_t feed_capacity = 65536;   // capacity of the feed accumulator
};

struct DdaBlock {
  enum class Kind : uint8_t { line, arc } kind = Kind::line;
  int64_t from[2] = {0, 0}, to[2] = {0, 0};  // nodes
  int64_t center[2] = {0, 0};                // arc: centre node
  int quadrant = 0;                          // arc: 0..3, the quadrant about the centre it lies in
  bool ccw = true;                           // arc: direction
  int64_t path = 1;                          // PATH word: capacity of the DDA registers
  uint32_t feed = 0;                         // feed word F
  double length_blu = 0.0;                   // programmed length
};

struct DdaProgram {
  double blu = 0.0;                 // m
  double speed = 0.0;               // m/s, programmed tangential speed
  DdaOptions options;
  bool closed = false;
  int64_t start[2] = {0, 0};
  std::vector<DdaBlock> blocks;
  size_t line_blocks = 0, arc_blocks = 0;
  size_t arcs_as_lines = 0;         // arc pieces whose rounded ends left no room for the circular DDA
  double length_m = 0.0;            // sum of the blocks' programmed lengths
};

// Turns lines and arcs (in metres, chained end to end) into DDA blocks on a grid of `blu` metres, for the
// tangential speed `speed`. Arcs are split at the quadrant boundaries. Throws InputError when the speed needs
// more DDA cycles per second than there are interrupts, or the feed word would round to zero.
DdaProgram make_dda_program(const std::vector<PathSegment>& segments, bool closed, double blu, double speed,
                            const DdaOptions& opt);

struct DdaStats {
  uint64_t cycles = 0;         // DDA cycles (iterations) run
  uint64_t interrupts = 0;     // interrupts from the start to the end of the last block
  uint64_t cleanup_steps = 0;  // arc steps the end-point clean-up issued where the register had not overflowed
};

// Runs the program through the interpolator. Every pulse goes to `sink` (may be null) with the time of the
// interrupt that produced it (interrupt J at J / interrupt_hz, rounded to the nanosecond); pulses of one cycle
// come x before y (line) or a before b (arc) with equal times.
CartesianResult run_dda(const DdaProgram& program, StepSink* sink, DdaStats* stats = nullptr);

}  // namespace polarcam
