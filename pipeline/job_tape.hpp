#pragma once
// Job -> tape glue: the header a job's tape starts with, and digitizing a job end to end.
#include <string>

#include "job/job.hpp"
#include "digitizer/tape.hpp"

namespace polarcam {

// Header fields known before digitizing: grid, work area, home, speed, provenance.
TapeHeader tape_header_for(const Job& job);
// Fields known after: start/end nodes, duration, closure, path length.
void complete_header(TapeHeader& h, const DigitizeResult& r);

struct DigitizedJob {
  ToolPathPtr path;
  PolarTrack track;
  SpeedProfilePtr profile;
  DigitizeResult result;
};

// Builds the tool path and its track, and digitizes it into `sink` (may be null). Errors name the job file.
DigitizedJob digitize_job(const Job& job, StepSink* sink);

}  // namespace polarcam
