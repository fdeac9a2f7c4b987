#pragma once
// Job -> Cartesian machine glue: the tool-centre path in the contour's frame, the line-and-arc program and the
// DDA, or the exact generator, and the tape header of a Cartesian tape (docs/cartesian.md).
#include <optional>
#include <string>

#include "job/job.hpp"
#include "cam/arc_fit.hpp"
#include "digitizer/tape.hpp"
#include "machine/cartesian/cartesian.hpp"
#include "machine/cartesian/dda.hpp"
#include "metrics/pulse_speed.hpp"

namespace polarcam {

enum class CartesianMethod { dda, exact };
const char* to_string(CartesianMethod m);

struct CartesianRun {
  CartesianMethod method = CartesianMethod::dda;
  ToolPathPtr path;          // tool-centre path, contour frame (no placement)
  double blu = 0.0;          // m
  double nominal_speed = 0;  // m/s
  double interrupt_rate = 0; // Hz (DDA)
  ArcFit fit;                // DDA: the lines and arcs
  DdaProgram program;        // DDA: the blocks
  DdaStats dda;              // DDA: cycles, interrupts, clean-up steps
  CartesianResult result;
  PulseSpeedStats speed;     // measured from the pulse rates of the tape (run_cartesian_job_to_tape)
};

// The tool-centre path in the Cartesian machine's frame (the contour's own frame): tool offset and direction of
// travel apply, the polar placement does not. Errors name the job file.
ToolPathPtr make_cartesian_job_path(const Job& job);

// Header fields known before stepping: axes, rule, resolution, speed, provenance (with the Cartesian settings).
TapeHeader cartesian_tape_header(const Job& job, CartesianMethod m, double interrupt_rate);
// Fields known after: start/end nodes, duration, closure, path length.
void complete_cartesian_header(TapeHeader& h, const CartesianResult& r);

// The interrupt rate a run uses: `override_hz` when given, else the job's [cartesian] interrupt_rate.
double cartesian_interrupt_rate(const Job& job, std::optional<double> override_hz);

// Builds the path and steps it with the chosen method into `sink` (may be null). Errors name the job file.
CartesianRun run_cartesian_job(const Job& job, CartesianMethod m, double interrupt_rate, StepSink* sink);

// The same into the tape `out` (all or nothing), or into a temporary tape when `out` is empty, and the speed
// measured from that tape in constant memory.
CartesianRun run_cartesian_job_to_tape(const Job& job, CartesianMethod m, double interrupt_rate, const std::string& out);

}  // namespace polarcam
