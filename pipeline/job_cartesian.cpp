#include "pipeline/job_cartesian.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cam/error.hpp"
#include "io/output.hpp"
#include "machine/cartesian/cartesian_exact.hpp"
#include "machine/cartesian/cartesian_track.hpp"

#ifndef POLARCAM_VERSION
#define POLARCAM_VERSION "0.0.0"
#endif

namespace polarcam {

const char* to_string(CartesianMethod m) { return m == CartesianMethod::dda ? "dda" : "exact"; }

double cartesian_interrupt_rate(const Job& job, std::optional<double> override_hz) {
  double f = override_hz.value_or(job.cartesian.interrupt_rate);
  if (!(f > 0.0) || !std::isfinite(f) || f > 1e9) throw InputError("the interrupt rate must be a frequency above 0 and up to 1 GHz");
  return f;
}

ToolPathPtr make_cartesian_job_path(const Job& job) {
  try {
    return make_tool_path(job.contour, Placement{}, job.tool, job.motion.travel);
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
}

TapeHeader cartesian_tape_header(const Job& job, CartesianMethod m, double interrupt_rate) {
  TapeHeader h;
  h.axes = TapeAxes::cartesian;
  h.rule = m == CartesianMethod::dda ? TapeRule::dda : TapeRule::exact_cartesian;
  h.res[0] = h.res[1] = job.cartesian.resolution;
  h.speed_mps = job.motion.nominal_speed();
  nlohmann::ordered_json c;
  c["method"] = to_string(m);
  c["resolution_m"] = job.cartesian.resolution;
  c["origin"] = "contour pole";
  if (m == CartesianMethod::dda) {
    c["tolerance_m"] = job.cartesian.tolerance;
    c["interrupt_rate_hz"] = interrupt_rate;
    c["feed_capacity"] = DdaOptions{}.feed_capacity;
  }
  nlohmann::ordered_json p;
  p["generator"] = std::string("polarcam ") + POLARCAM_VERSION;
  p["job"] = job.provenance;
  p["cartesian_machine"] = c;
  h.provenance = p.dump();
  return h;
}

void complete_cartesian_header(TapeHeader& h, const CartesianResult& r) {
  for (int a = 0; a < 2; ++a) {
    h.start[a] = r.start[a];
    h.end[a] = r.end[a];
  }
  h.duration_ticks = static_cast<uint64_t>(r.duration_ns);
  h.closed = r.closed;
  h.returns_to_start = r.returns_to_start;
  h.path_length_m = r.path_length_m;
}

CartesianRun run_cartesian_job(const Job& job, CartesianMethod m, double interrupt_rate, StepSink* sink) {
  CartesianRun run;
  run.method = m;
  run.blu = job.cartesian.resolution;
  run.nominal_speed = job.motion.nominal_speed();
  run.interrupt_rate = interrupt_rate;
  run.path = make_cartesian_job_path(job);
  try {
    if (m == CartesianMethod::exact) {
      CartesianTrack track = CartesianTrack::build(*run.path);
      SpeedProfilePtr profile = make_job_profile(job, *run.path, track.length());
      run.result = step_exact(track, run.blu, *profile, sink);
    } else {
      if (job.motion.accel) throw InputError("[motion] accel: the DDA runs every block at a constant feed; remove it or use --method exact");
      if (job.motion.rollers)
        throw InputError("[motion] speed_profile = \"template\": the DDA runs every block at a constant feed; use --method exact");
      if (!job.motion.table.empty())
        throw InputError("[motion] speed_profile: the DDA runs every block at a constant feed; give 'speed' or use --method exact");
      // the schedules made from the job's dynamics or its cut are not a feed either: refused, not run at 'speed'
      if (job.motion.time_optimal)
        throw InputError("[motion] speed_profile = \"time-optimal\": the DDA runs every block at a constant feed; give "
                         "'speed' alone for a DDA run");
      if (job.motion.constant_force)
        throw InputError("[motion] speed_profile = \"constant-force\": the DDA runs every block at a constant feed; "
                         "use --method exact");
      ArcFitOptions fo;
      fo.tolerance = job.cartesian.tolerance;
      run.fit = fit_lines_and_arcs(*run.path, fo);
      DdaOptions dopt;
      dopt.interrupt_hz = interrupt_rate;
      run.program = make_dda_program(run.fit.segments, run.path->closed(), run.blu, job.motion.speed, dopt);
      run.result = run_dda(run.program, sink, &run.dda);
    }
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
  return run;
}

CartesianRun run_cartesian_job_to_tape(const Job& job, CartesianMethod m, double interrupt_rate, const std::string& out) {
  // without an output file, or with one that is written through (a device, a FIFO: it cannot be read back), the
  // tape goes to a temporary file, removed at the end: the speed is measured from it
  static int counter = 0;
  const bool through = !out.empty() && output_writes_through(out);
  std::unique_ptr<TempFile> temp;
  if (out.empty() || through)
    temp = std::make_unique<TempFile>((std::filesystem::temp_directory_path() /
                                       ("polarcam-dda-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(counter++) + ".tape"))
                                          .string());
  const std::string path = temp ? temp->path() : out;
  TapeHeader h = cartesian_tape_header(job, m, interrupt_rate);
  CartesianRun run;
  {
    TapeWriter w(path, h);
    run = run_cartesian_job(job, m, interrupt_rate, &w);
    complete_cartesian_header(h, run.result);
    w.finish(h);
  }
  run.speed = measure_tape_speed(path, run.nominal_speed);
  if (through) copy_to_output(path, out);
  return run;
}

}  // namespace polarcam
