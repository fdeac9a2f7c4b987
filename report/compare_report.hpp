#pragma once
// The comparison as a self-contained HTML report (report/html.hpp): what was compared, the verdict per attribute in
// plain words, the side-by-side measurements, both staircases drawn over the contour near each machine's worst
// point, and the tangential speed along the path of both machines. Written all or nothing.
#include <string>

#include "pipeline/compare.hpp"

namespace polarcam {

// `c` must have been made with CompareOptions::figures. Throws InputError for an unwritable file.
void write_compare_report(const Comparison& c, const std::string& path);

}  // namespace polarcam
