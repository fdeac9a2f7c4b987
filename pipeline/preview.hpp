#pragma once
// What `polarcam preview` draws, computed: the tool path a job asks for, the motion the machine makes stepping its
// tape (the nodes it stands on, in order), where it starts and ends, and the stretches where the tool does not
// move at the requested speed (near the centre of a theta-rho pattern, where the arm runs at its top angular
// speed). Millimetres about the machine pole; report/preview_figure renders it.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "job/job.hpp"
#include "pipeline/job_tape.hpp"

namespace polarcam {

struct Polyline {
  std::vector<double> x, y;  // mm
};

struct Preview {
  std::string title;
  std::optional<double> r_min_mm, r_max_mm;  // the work area
  std::vector<Polyline> path;    // the job's tool path, one polyline a contour (empty for a tape alone)
  // The machine's nodes in order, thinned to points `resolution_mm` apart: with the tool down (drawing), and with
  // the tool up (the rapid moves between the contours of a job on a machine that lifts its tool). Each run starts
  // at the last point of the one before.
  std::vector<Polyline> stepped;
  std::vector<Polyline> rapids;
  std::vector<Polyline> slowed;  // stretches of the path where the tool moves below 99 % of the requested speed
  double start[2] = {0, 0}, end[2] = {0, 0};
  uint64_t steps = 0;
};

// A job: its tool path, and the tape digitizing it would write (not written); a lifting job's contours and its
// rapid moves (pipeline/job_tape). The job is digitized once; `digitized` (may be null) receives what that gave.
Preview preview_job(const Job& job, double resolution_mm, DigitizedJob* digitized = nullptr);
// A tape alone: the nodes its steps walk (a coupled arm's radial motor is taken back to the ball's radius with
// the coupling its provenance records), split at its tool events into drawn runs and rapids.
Preview preview_tape(const std::string& path, double resolution_mm);

}  // namespace polarcam
