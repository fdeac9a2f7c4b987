#pragma once
// Writing a job back with another placement (`polarcam optimize --write-job`).
#include <string>

#include "cam/toolpath.hpp"

namespace polarcam {

// The text of the job file `job_path` with [placement] set to `pl` (exact: 17 significant digits, in m and rad),
// as a file to be written at `out_path`: relative file names (the machine file, a contour's data file) are
// rewritten relative to the new location. `note` goes into a comment at the top (one line).
std::string job_with_placement(const std::string& job_path, const Placement& pl, const std::string& out_path,
                               const std::string& note);

}  // namespace polarcam
