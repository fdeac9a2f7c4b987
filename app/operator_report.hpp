#pragma once
// The operator's report (`polarcam report JOB.toml -o report.html`, docs/operator-report.md): one self-contained
// HTML page to read before running a job. Sections (with these element ids): verdict, job, workarea, tape,
// accuracy, torque, capacity, pole, tradeoff, glossary. Every number comes from the production pipeline
// (digitize, the error meters, analyze, capacity, the pole searches).
#include <string>

#include "app/job.hpp"

namespace polarcam::cli {

struct ReportOptions {
  int map_size = 31;        // poles per side of the pole survey
  int max_evaluations = 0;  // budget of each pole search (0: their defaults)
  int curve_points = 12;    // speeds on the capacity curve
  int threads = 0;          // 0: all cores; the report does not depend on it
};

struct OperatorReport {
  std::string html;
  bool go = false;  // the job's verdict
};

// Throws InputError naming the job file.
OperatorReport operator_report(const Job& job, const ReportOptions& o);

}  // namespace polarcam::cli
