#pragma once
// The "Cutting" section of an HTML report for a job with a milling load (pipeline/job_process.hpp): the cut, the
// tool's limits against the largest forces along the path, what binds the feed on each stretch, and the figure of
// force and feed along the path. Rendering only; a separate function so that the operator report can add it.
#include "pipeline/job_process.hpp"
#include "report/html.hpp"

namespace polarcam {

// Appends the section (a level-2 heading with id "cutting") to `rep`.
void add_cutting_section(html::Report& rep, const Job& job, const ProcessRun& r);

}  // namespace polarcam
