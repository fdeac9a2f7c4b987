#include "app/job_cartesian.hpp"

#include <cmath>

#include "cam/error.hpp"
#include "machine/cartesian_exact.hpp"
#include "machine/cartesian_track.hpp"

#ifndef POLARCAM_VERSION
#define POLARCAM_VERSION "0.0.0"
#endif

namespace polarcam {
namespace {

// Forwards each step to the speed meter and to the tape (when there is one).
class Tee final : public StepSink {
 public:
  Tee(StepSink* a, StepSink* b) : a_(a), b_(b) {}
  void step(int axis, int dir, int64_t t_ns) override {
    if (a_) a_->step(axis, dir, t_ns);
    if (b_) b_->step(axis, dir, t_ns);
  }

 private:
  StepSink *a_, *b_;
};

double nominal_speed(const Job& job) { return job.motion.table.empty() ? job.motion.speed : job.motion.table.front().v; }

}  // namespace

const char* to_string(CartesianMethod m) { return m == CartesianMethod::dda ? "dda" : "exact"; }

double cartesian_interrupt_rate(const Job& job, std::optional<double> override_hz) {
  double f = override_hz.value_or(job.cartesian.interrupt_rate);
  if (!(f > 0.0) || !std::isfinite(f) || f > 1e9) throw InputError("the interrupt rate must be a frequency above 0 and up to 1 GHz");
  return f;
}

TapeHeader cartesian_tape_header(const Job& job, CartesianMethod m, double interrupt_rate) {
  TapeHeader h;
  h.axes = TapeAxes::cartesian;
  h.rule = m == CartesianMethod::dda ? TapeRule::dda : TapeRule::exact_cartesian;
  h.res[0] = h.res[1] = job.cartesian.resolution;
  h.speed_mps = nominal_speed(job);
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
  run.nominal_speed = nominal_speed(job);
  run.interrupt_rate = interrupt_rate;
  try {
    // the tool-centre path in the contour's own frame: tool offset and direction apply, the placement does not
    run.path = make_tool_path(job.contour, Placement{}, job.tool, job.motion.travel);
    PulseSpeedMeter meter(run.blu, run.blu);
    Tee tee(&meter, sink);
    if (m == CartesianMethod::exact) {
      CartesianTrack track = CartesianTrack::build(*run.path);
      SpeedProfilePtr profile = make_job_profile(job, track.length());
      run.result = step_exact(track, run.blu, *profile, &tee);
    } else {
      if (job.motion.accel) throw InputError("[motion] accel: the DDA runs every block at a constant feed; remove it or use --method exact");
      if (!job.motion.table.empty())
        throw InputError("[motion] speed_profile: the DDA runs every block at a constant feed; give 'speed' or use --method exact");
      ArcFitOptions fo;
      fo.tolerance = job.cartesian.tolerance;
      run.fit = fit_lines_and_arcs(*run.path, fo);
      DdaOptions dopt;
      dopt.interrupt_hz = interrupt_rate;
      run.program = make_dda_program(run.fit.segments, run.path->closed(), run.blu, job.motion.speed, dopt);
      run.result = run_dda(run.program, &tee, &run.dda);
    }
    run.speed = meter.stats(run.nominal_speed);
  } catch (const InputError& e) {
    throw InputError(job.file + ": " + e.what());
  }
  return run;
}

}  // namespace polarcam
