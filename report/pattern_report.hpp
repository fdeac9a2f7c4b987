#pragma once
// The report of a pattern (`polarcam report PATTERN --machine M --speed V -o report.html` when the machine has no
// dynamics or a coupled arm; docs/patterns.md): one self-contained HTML page with the verdict (can the motors step
// it), the drawing on the table, the time it takes and where the requested speed is not kept, the tape's steps
// and step rates, and what is not analysed and why. Rendering only: the numbers come from
// pipeline/pattern_study.
#include "job/job.hpp"
#include "pipeline/pattern_study.hpp"
#include "report/operator_report.hpp"

namespace polarcam::cli {

OperatorReport pattern_report(const Job& job, const PatternStudy& study);

}  // namespace polarcam::cli
