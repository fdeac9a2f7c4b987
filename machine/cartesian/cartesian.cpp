#include "machine/cartesian/cartesian.hpp"

#include <cmath>
#include <sstream>

#include "cam/error.hpp"

namespace polarcam {

int64_t cartesian_node(double coordinate_m, double blu) {
  const double f = coordinate_m / blu;
  if (!(std::abs(f) < 0x1p50)) {
    std::ostringstream os;
    os.precision(6);
    os << "the path reaches " << coordinate_m * 1e3 << " mm from the origin, too far for a resolution of " << blu * 1e3
       << " mm";
    throw InputError(os.str());
  }
  return static_cast<int64_t>(std::floor(f + 0.5));
}

void check_step_budget(double length_m, double blu) {
  // each BLU of path moves one or both axes by a step: at most 2 steps per BLU
  if (!(2.0 * length_m / blu <= 1e10)) {
    std::ostringstream os;
    os.precision(6);
    os << "a path of " << length_m * 1e3 << " mm on a grid of " << blu * 1e3
       << " mm would take more than 10^10 steps: coarsen the resolution";
    throw InputError(os.str());
  }
}

}  // namespace polarcam
