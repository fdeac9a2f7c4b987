#pragma once
// What the report of a pattern shows, computed: for a job whose machine has no dynamics (masses, motors) or whose
// arm is coupled (a sand table), the operator's full report (torques, capacity, pole study) does not apply, but
// the operator still wants to know what the machine will draw, how long it takes, where it cannot keep the
// requested speed and whether a motor would have to step faster than it can. report/pattern_report renders it.
#include <string>
#include <vector>

#include "digitizer/digitize.hpp"
#include "job/job.hpp"
#include "pipeline/job_tape.hpp"
#include "pipeline/preview.hpp"

namespace polarcam {

struct PatternStudy {
  DigitizeResult dig;                   // the tape's summary (not written)
  Preview preview;                      // the tool path, the stepped motion, the slowed stretches
  std::vector<StepRateExcess> excess;   // axes whose motors would step faster than their max_step_rate
  double speed_mps = 0.0;               // the requested speed
  double drawn_length_m = 0.0;          // the path's length as drawn (the preview's samples of it: chords)
  double nominal_time_s = 0.0;          // the drawn length at the requested speed throughout
  double rapid_time_s = 0.0;            // of the rapid moves with the tool up (a machine that lifts its tool)
  double rapid_length_m = 0.0;
  double slowed_length_m = 0.0;         // of the path below 99 % of the requested speed (from the preview's samples)
  size_t contours = 1;
  bool has_dynamics = false;            // the machine file describes masses and motors
  bool coupled = false;                 // the arm is coupled to the radial axis
  bool go() const { return excess.empty(); }
};

// Throws InputError naming the job file (a path outside the work area, ...).
PatternStudy study_pattern(const Job& job);

// True when `polarcam report` gives a job the pattern report instead of the operator's report: its machine has no
// dynamics, or a coupled arm (whose torques the dynamics model does not describe).
bool pattern_report_applies(const Job& job);

}  // namespace polarcam
