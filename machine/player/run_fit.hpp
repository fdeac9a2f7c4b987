#pragma once
// The search for the next run of one axis (docs/controller-protocol.md, "Step schedule"): the longest cubic run
// whose steps all land in their tick windows, with parameters that are short on the wire.
//
// A run from clock C puts its k-th step at C + P(k), P(k) = offset + k I + C(k,2) A + C(k,3) B (32.32 ticks), and
// step k must fire at a tick floor(C + P(k)) in its window [lo_k, hi_k]: a band lo_k <= C + P(k) < hi_k + 1 that
// is linear in (offset, I, A, B). The longest run is found by a discrete minimax (Remez exchange) fit of P to the
// bands, grown one step at a time; the parameters are then fixed from the highest order down, each to the value
// with the fewest significant bits (relative to the run predicted by the previous one) that still lets the lower
// orders fit. This is done in double precision and only proposes: compress_schedule executes every proposal with
// the controller's integer arithmetic and keeps only the steps that land in their windows.
#include <cstdint>

#include "machine/player/int128.hpp"
#include "machine/player/schedule.hpp"

namespace polarcam {

// A proposed run (count >= 1 when limit >= 1). Parameters in 1/2^32 ticks.
struct RunProposal {
  uint32_t count = 0;
  int64_t offset = 0, interval = 0, add = 0, add2 = 0;
};

// w[0 .. limit-1]: the windows of the next steps of one axis (same direction); clock: the axis clock (32.32
// ticks, absolute) before the run; ref: the wire's prediction of the next run (the previous one continued);
// shape: which coefficients may be used (the others stay zero).
RunProposal propose_run(const StepWindow* w, uint32_t limit, i128 clock, const RunRef& ref,
                        const RunShape& shape = RunShape{});

}  // namespace polarcam
