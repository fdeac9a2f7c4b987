#include "machine/cartesian.hpp"

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

}  // namespace polarcam
