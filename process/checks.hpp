#pragma once
// Checks shared by the process models.
#include <cmath>

namespace polarcam::process {

// A quantity that must be finite and above zero.
inline bool positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace polarcam::process
