#pragma once
// A job's tool path for sand tables and viewers: the theta-rho file (.thr, rho normalised to the machine's r_max),
// G-code (machine/gcode, from the machine file's [gcode] table) and an SVG drawing of the path (cam/svg_export).
// The file is written to a stream (the caller's all-or-nothing output), never held whole.
#include <iosfwd>
#include <optional>
#include <string>

#include "io/progress.hpp"
#include "job/job.hpp"
#include "machine/gcode/gcode.hpp"

namespace polarcam {

enum class ExportFormat { thr, gcode, svg };

// The finest tolerance of an export, 0.1 um: far below what any machine follows, and the number of vertices grows as
// the inverse square root of the tolerance (a finer one asks for millions of them and for positions beyond the
// precision of the numbers they are computed from).
inline constexpr double kMinExportTolerance = 1e-7;

// InputError naming --tolerance unless it is a finite length of at least kMinExportTolerance.
void check_export_tolerance(double tolerance);

struct ExportOptions {
  ExportFormat format = ExportFormat::thr;
  double tolerance = 1e-4;              // m: theta-rho segments within this of the path; the SVG's chords within a quarter of it
                                        // (at least kMinExportTolerance)
  std::optional<FeedMode> feed_mode;    // G-code: overrides the [gcode] table's feed_mode
};

struct ExportResult {
  std::string content;                  // the file's bytes (the overload without a stream only)
  size_t vertices = 0;                  // theta-rho vertices (thr, gcode)
  size_t points = 0;                    // polyline points (svg)
  double path_length_m = 0.0;           // the tool path's length
  double rho_max_m = 0.0;               // the largest distance of the path from the pole (of its vertices or points)
  std::optional<GcodeStats> gcode;      // gcode: the program's statistics
};

// Exports the job's tool path. InputError (naming the job file) for a machine without r_max (thr), without a
// [gcode] table (gcode), a path that leaves r_max or the table radius, a speed profile (gcode: a constant speed
// is needed), or a bad tolerance.
// `progress`: the stages done (the path, its vertices or points, the file), 0 to 1.
// The file is written to `out` (the caller checks the stream).
ExportResult export_job(const Job& job, const ExportOptions& o, std::ostream& out, const Progress& progress = {});
// The same with the file's bytes in the result's `content` (small files, tests).
ExportResult export_job(const Job& job, const ExportOptions& o, const Progress& progress = {});

// "thr", "gcode", "svg"
const char* to_string(ExportFormat f);

}  // namespace polarcam
