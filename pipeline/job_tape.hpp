#pragma once
// Job -> tape glue: the header a job's tape starts with, and digitizing a job end to end.
#include <algorithm>
#include <optional>

#include "io/progress.hpp"
#include <string>
#include <vector>

#include "job/job.hpp"
#include "cam/theta_rho_path.hpp"
#include "digitizer/tape.hpp"
#include "digitizer/theta_rho.hpp"

namespace polarcam {

// Header fields known before digitizing: grid, work area, home, speed, provenance.
TapeHeader tape_header_for(const Job& job);
// Fields known after: start/end nodes, duration, closure, path length.
void complete_header(TapeHeader& h, const DigitizeResult& r);

// The theta-rho polyline the job's tool path is, when it is one (a theta-rho contour drawn as it is: no
// placement, no tool radius, forward from its start); nullptr otherwise.
const ThetaRhoPath* job_theta_rho_path(const Curve& path);
// Near the centre of a theta-rho path, the radius whose arc times a turn of the arm (digitizer/theta_rho.hpp):
// the job's top speed over the machine's max_angular_speed, 0 when the machine gives none.
double job_timing_radius(const Job& job);
// The polar track (r, theta) of a path of the job: from the vertices of a theta-rho polyline (exact through the
// centre), else from x and y. Errors name the job file.
PolarTrack job_polar_track(const Job& job, const Curve& path);

// A rapid move between two contours of a job on a machine that lifts its tool: the segment linear in the motor
// coordinates r and theta (a theta-rho segment, theta the machine's angle) from the end of one contour to the start
// of the next, stepped with the tool up at the machine's rapid_speed.
struct RapidMove {
  ThetaRho from, to;        // rho in m, theta in rad (the machine's angle, on the branch the tape steps)
  double length_m = 0.0;    // the tool point's path along it
  double duration_s = 0.0;
  uint64_t steps = 0;       // steps of both motors
};

// The contours of a lifting job, each stepped as its own path, and the rapid moves between them.
struct LiftedJob {
  std::vector<ToolPathPtr> paths;   // the contours' tool paths, in order
  std::vector<PolarTrack> tracks;   // their tracks (r, theta before the shift)
  std::vector<double> shifts;       // the angular branch each is stepped on (rad added to its track's theta)
  std::vector<RapidMove> rapids;    // between contour k and k + 1 (none when the two points coincide)
  double drawn_length_m = 0.0, rapid_length_m = 0.0, rapid_time_s = 0.0;
  uint64_t rapid_steps = 0;
};

struct DigitizedJob {
  ToolPathPtr path;                 // a lifting job: the first contour's
  PolarTrack track;                 // a lifting job: the first contour's; empty for a theta-rho polyline
  // A theta-rho polyline (job_theta_rho_path): its track streamed from the path's vertices (the arm's, with the
  // machine's coupling; PolylineTrack::for_each(f, true) gives the polar track's pieces), never held piece by
  // piece, so digitizing a pattern takes memory that does not grow with its length. It refers to `path`.
  std::optional<PolylineTrack> polyline;
  SpeedProfilePtr profile;          // a lifting job: the first contour's
  DigitizeResult result;            // the whole tape
  std::optional<LiftedJob> lifted;  // a job of several contours on a machine that lifts its tool
};

// True when the job's contours are stepped one by one with the tool lifted between them (Job::parts).
bool job_lifts_tool(const Job& job);
// The speed of the rapid moves: the machine's rapid_speed, else the job's (first) speed.
double job_rapid_speed(const Job& job);

// The ranges of r (m) and of theta (rad, on the branches stepped) of what the tool draws: the path, or a lifting
// job's contours (the rapid moves lie between their ends).
struct PathRanges {
  double r_min = 0, r_max = 0, theta_min = 0, theta_max = 0;
};

// Builds the tool path and its track, and digitizes it into `sink` (may be null). Errors name the job file.
// A lifting job (job_lifts_tool): the first contour as a job of one contour would be (its start node, its angular
// branch), then for each next contour: tool up (sink->tool), the rapid move, tool down, the contour, on the arm's
// turn nearest the end of the rapid, its quantisers continuing from the node the rapid ended on. The result's
// times, steps and length are those of the whole tape (contours and rapids).
// `progress`: the share of the path's time digitized.
DigitizedJob digitize_job(const Job& job, StepSink* sink, const Progress& progress = {});
PathRanges path_ranges(const DigitizedJob& d);

// A sink that passes every step on to `inner` (may be null) and reports the share of `total_s` (the path's time)
// the steps have reached, every 4096 steps.
class ProgressSink final : public StepSink {
 public:
  ProgressSink(StepSink* inner, const Progress& progress, double total_s)
      : inner_(inner), progress_(progress), total_ns_(total_s * 1e9) {}
  void step(int axis, int dir, int64_t t_ns) override {
    if (inner_) inner_->step(axis, dir, t_ns);
    if ((++count_ & 0xfff) == 0 && total_ns_ > 0.0) {
      const double f = std::min(1.0, static_cast<double>(t_ns) / total_ns_);
      if (f > reported_) progress_(reported_ = f);
    }
  }
  void tool(bool down, int64_t t_ns) override {
    if (inner_) inner_->tool(down, t_ns);
  }
  void begin(int64_t n, int64_t m) override {
    if (inner_) inner_->begin(n, m);
  }

 private:
  StepSink* inner_;
  Progress progress_;
  double total_ns_;
  uint64_t count_ = 0;
  double reported_ = 0.0;
};

// A tape axis whose steps come faster than its motor can step ([machine.motor] max_step_rate, in motor steps/s).
// A tape step is not a motor step: the drive train turns one into `motor_steps_per_tape_step` motor steps
// (radial: radial_resolution x screw turns per metre x motor steps per turn; angular: the motor steps per arm
// turn over the tape's angular steps per turn), as the dynamics convert path rates into motor step rates, so the
// tape's largest rate (V |d step / ds|, geometric) times that is compared with the limit.
struct StepRateExcess {
  int axis = 0;                           // 0 radial, 1 angular
  double tape_rate_hz = 0.0;              // tape steps per second
  double motor_steps_per_tape_step = 1.0;
  double motor_rate_hz = 0.0;             // motor steps per second
  double limit_hz = 0.0;                  // the motor's max_step_rate
};
// The axes over their limit (empty for a machine without dynamics or without max_step_rate).
std::vector<StepRateExcess> step_rate_excess(const Job& job, const DigitizeResult& r);

}  // namespace polarcam
