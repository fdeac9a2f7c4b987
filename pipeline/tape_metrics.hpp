#pragma once
// Job + tape -> error metrics: reads a step tape and measures its quasi-static path against the job's tool path,
// for either kind of tape (docs/area-error.md, docs/compare.md). A polar tape is measured against the tool path in
// the polar machine's frame (make_job_path), a Cartesian tape against the tool path in the contour's own frame
// (make_cartesian_job_path). Errors name the tape and the job.
#include <string>

#include "job/job.hpp"
#include "digitizer/tape.hpp"
#include "io/progress.hpp"
#include "metrics/cartesian_error.hpp"
#include "metrics/error_metrics.hpp"

namespace polarcam {

struct PolarTapeMetrics {
  ErrorMetrics m;
  Grid grid;  // the tape's
  TapeRule rule = TapeRule::nearest;
};
// `segments`: F_sum, F_dif, F1 segments (0: the job's [optimize] segments). `progress`: the share of the tape's
// records read. `threads`: 2 or more runs the area meter on a thread of its own beside the deviation (the same
// results).
PolarTapeMetrics polar_tape_metrics(const Job& job, const std::string& tape, int segments,
                                    const Progress& progress = {}, int threads = 1);

struct CartesianTapeMetrics {
  CartesianErrorMetrics m;
  double blu = 0.0;  // the tape's
  TapeRule rule = TapeRule::dda;
};
CartesianTapeMetrics cartesian_tape_metrics(const Job& job, const std::string& tape, const Progress& progress = {});

}  // namespace polarcam
