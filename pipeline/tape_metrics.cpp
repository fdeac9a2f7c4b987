#include "pipeline/tape_metrics.hpp"

#include <algorithm>
#include <optional>

#include "pipeline/job_tape.hpp"
#include "pipeline/job_cartesian.hpp"
#include "cam/error.hpp"
#include "digitizer/tape.hpp"
#include "machine/cartesian/cartesian_track.hpp"

namespace polarcam {

PolarTapeMetrics polar_tape_metrics(const Job& job, const std::string& tape, int segments, const Progress& progress,
                                    int threads) {
  // the area and deviation meters measure the staircase of a polar machine, whose radial steps move the tool
  // radially and angular steps about the pole; on a coupled arm an angular step also moves the ball radially
  if (job.machine.coupling != 0.0)
    throw InputError("the machine's radial motor is coupled to its arm (coupling): the error meters measure "
                     "tapes of uncoupled polar machines; give a machine file without 'coupling' to measure the path",
                     job.file);
  if (job_lifts_tool(job))
    throw InputError("the machine lifts its tool between the drawing's " + std::to_string(job.parts.size()) +
                         " contours: the error metrics measure one contour; measure each contour as a job of its own",
                     job.file);
  const ToolPathPtr path = make_job_path(job);
  const PolarTrack track = job_polar_track(job, *path);
  TapeReader rd(tape);
  const TapeHeader& h = rd.header();
  if (h.axes != TapeAxes::polar) throw InputError("a Cartesian tape, not a polar one", tape);
  refuse_tool_events(h, tape, "the error metrics", "they measure one contour's staircase against its path; measure each contour as a job of its own");
  PolarTapeMetrics out;
  out.rule = h.rule;
  Grid& g = out.grid;
  g.dr = h.res[0];
  g.dtheta = h.res[1];
  g.steps_per_rev = h.steps_per_rev;
  in_file(tape, [&] { g.validate(); });
  // streamed: the meters measure each sector as the tape goes by, in a window of constant size; should the
  // staircase or the contour come back to a sector measured already, the tape is read again into recording
  // meters (same results, memory in proportion to the tape)
  const int nseg = segments > 0 ? segments : job.optimize.segments;
  const double total = static_cast<double>(std::max<uint64_t>(h.record_count, 1));
  for (int pass = 0; pass < 2; ++pass) {
    ErrorMeters em;
    em.reset(*path, track, g, nseg);
    em.set_parallel(threads > 1);
    if (pass == 0) em.stream_from(h.start[0], h.start[1]);
    std::optional<TapeReader> again;
    if (pass == 1) again.emplace(tape);
    TapeReader& in = pass == 0 ? rd : *again;
    StepRecord r;
    while (in.next(r)) {  // the reader checks totals and checksums at the end
      em.record(r.axis, r.dir);
      if ((in.records_read() & 0xffff) == 0) report_progress(progress, static_cast<double>(in.records_read()) / total);
    }
    try {
      out.m = em.finish(h.start[0], h.start[1]);
    } catch (const InputError& e) {
      throw InputError(tape + " against " + job.file + ": " + e.what());
    }
    if (pass == 1 || em.streamed()) break;
  }
  return out;
}

CartesianTapeMetrics cartesian_tape_metrics(const Job& job, const std::string& tape, const Progress& progress) {
  const ToolPathPtr path = make_cartesian_job_path(job);
  const CartesianTrack track = in_file(job.file, [&] { return CartesianTrack::build(*path); });
  TapeReader rd(tape);
  const TapeHeader& h = rd.header();
  if (h.axes != TapeAxes::cartesian) throw InputError("a polar tape, not a Cartesian one", tape);
  refuse_tool_events(h, tape, "the error metrics", "they measure one contour's staircase against its path; measure each contour as a job of its own");
  if (!(h.res[0] > 0.0) || h.res[0] != h.res[1])
    throw InputError("the x and y resolutions must be equal and above zero (the header has " +
                     std::to_string(h.res[0]) + " and " + std::to_string(h.res[1]) + " m)", tape);
  CartesianTapeMetrics out;
  out.rule = h.rule;
  out.blu = h.res[0];
  CartesianErrorMeters em;
  em.reset(*path, track, out.blu);
  StepRecord r;
  const double total = static_cast<double>(std::max<uint64_t>(h.record_count, 1));
  while (rd.next(r)) {
    em.record(r.axis, r.dir);
    if ((rd.records_read() & 0xffff) == 0) report_progress(progress, static_cast<double>(rd.records_read()) / total);
  }
  try {
    out.m = em.finish(h.start[0], h.start[1]);
  } catch (const InputError& e) {
    throw InputError(tape + " against " + job.file + ": " + e.what());
  }
  return out;
}

}  // namespace polarcam
