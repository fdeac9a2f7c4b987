#pragma once
// Pattern files as jobs: every command that takes a job file also takes a pattern (.thr, .svg, .dxf, .csv) with
// a machine file (--machine) and a speed (--speed). The job made from a pattern has the pattern as its contour,
// the machine's pole as the contour's pole (no placement), a tool of zero radius, and the given speed
// (docs/patterns.md). An SVG drawing is centred on the pole and scaled to fit the work area (the circle of the
// machine's r_max, less 2 %); several contours (an SVG's subpaths) are joined in order into one theta-rho path,
// each contour within `tolerance` of its curve and the connecting moves linear in theta and rho, as a sand table
// draws them; a single contour keeps its exact curve. An image (a template: .png, .pbm, .pgm) is traced into its
// outlines and holes (cam/image_trace.hpp), kept at its physical size with its centre on the pole, and joined so.
// On a machine that lifts its tool (tool_lift) the contours are
// also kept one by one (Job::parts), to be joined by rapid moves with the tool up.
#include <optional>
#include <string>
#include <vector>

#include "cam/image_trace.hpp"
#include "cam/theta_rho_path.hpp"
#include "job/job.hpp"

namespace polarcam {

// The most angular steps a theta-rho pattern may need on its machine (a tape of some 30 GB, a month of stepping at
// 4 kHz): a pattern beyond it is refused before its track is built (its theta is most likely not in radians).
inline constexpr double kMaxPatternSteps = 1e10;

// Refuses (InputError naming `where`) a theta-rho pattern whose theta travel, the least the arm turns through,
// needs more than kMaxPatternSteps angular steps of `dtheta` rad: before its track is built and walked.
void check_pattern_travel(const std::vector<ThetaRho>& vertices, double dtheta, const std::string& where);

struct PatternOptions {
  std::string machine_file;        // --machine: required for a pattern, refused for a job file
  std::optional<double> speed;     // --speed (m/s): required for a pattern where used (speed_used); overrides a job's [motion] speed
  double tolerance = 1e-4;         // m: contours of a drawing joined into one theta-rho path stay this close
  TraceOptions trace;              // an image: how it is traced (its pixel size, threshold, ...)
  // false for a command whose result does not depend on the speed (the geometry alone: `error`, an export to
  // .thr or SVG, a pole search for the area error): a pattern then needs no --speed, and a --speed given (with a
  // pattern or a job file) is refused as it would be ignored. The job is made with kUnusedSpeed.
  bool speed_used = true;
};

// The speed of a pattern job made for a command that does not use it (PatternOptions::speed_used false): 1 m/s,
// written nowhere.
inline constexpr double kUnusedSpeed = 1.0;

// True for the file types read as patterns (by extension, case-insensitive): .thr, .svg, .dxf, .csv, and the
// images .png, .pbm, .pgm.
bool is_pattern_file(const std::string& path);

// A job file (TOML) read by load_job, or a pattern made into a job. Throws InputError naming the file or the
// option (--machine, --speed) that is missing or wrong.
Job load_job_or_pattern(const std::string& path, const PatternOptions& o);

}  // namespace polarcam
