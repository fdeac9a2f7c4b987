#include "digitizer/grid.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "cam/error.hpp"
#include "cam/format.hpp"

namespace polarcam {

void Grid::validate() const {
  if (!(dr > 0.0) || !std::isfinite(dr)) throw InputError("the radial resolution must be a positive length");
  if (!(dtheta > 0.0) || !std::isfinite(dtheta)) throw InputError("the angular resolution must be a positive angle");
  if (dr < kMinRadialResolution)
    throw InputError("the radial resolution " + significant(dr) + " m is finer than the finest a tape holds (1e-12 m)");
  if (dtheta < 2.0 * std::numbers::pi / static_cast<double>(kMaxStepsPerRev))
    throw InputError("the angular resolution " + significant(dtheta) +
                     " rad is finer than the finest a tape holds (2^40 = 1099511627776 steps per revolution)");
  if (steps_per_rev < 0 || steps_per_rev > kMaxStepsPerRev)
    throw InputError("angular steps per revolution must be from 0 to 2^40 (1099511627776), not " +
                     std::to_string(steps_per_rev));
  if (dtheta > std::numbers::pi / 4) throw InputError("the angular resolution is coarser than an eighth of a turn");
  if (!(r_min >= 0.0) || !std::isfinite(r_min)) throw InputError("r_min must be zero or a positive length");
  if (r_max && (!std::isfinite(*r_max) || !(*r_max > r_min))) throw InputError("r_max must be greater than r_min");
  if (theta_min.has_value() != theta_max.has_value())
    throw InputError("give both theta_min and theta_max, or neither (unlimited rotation)");
  if (theta_min && (!std::isfinite(*theta_min) || !std::isfinite(*theta_max) || !(*theta_max > *theta_min)))
    throw InputError("theta_max must be greater than theta_min");
  if (!std::isfinite(home_r) || !std::isfinite(home_theta)) throw InputError("the home position must be finite");
  if (r_max && (*r_max / dr > 4e15)) throw InputError("the radial resolution is too fine for the work area");
  if (r_max && dr > *r_max - r_min)
    throw InputError("the radial resolution " + significant(dr * 1e3) + " mm is coarser than the work area's radial span (" +
                     significant((*r_max - r_min) * 1e3) + " mm from r_min to r_max): no radial step fits in it");
  if (r_min / dr > kMaxNodeIndex || (r_max && *r_max / dr > kMaxNodeIndex))
    throw InputError("the work area spans more than 2^50 radial steps: give a coarser radial resolution or a smaller r_max");
  if (std::abs(home_r) / dr > kMaxNodeIndex || std::abs(home_theta) / dtheta > kMaxNodeIndex)
    throw InputError("the home position lies more than 2^50 steps from node 0");
  if (theta_min && (std::abs(*theta_min) / dtheta > kMaxNodeIndex || std::abs(*theta_max) / dtheta > kMaxNodeIndex))
    throw InputError("theta_min or theta_max lies more than 2^50 angular steps from 0");
}

int64_t Grid::home_n() const { return static_cast<int64_t>(std::floor(home_r / dr + 0.5)); }
int64_t Grid::home_m() const { return static_cast<int64_t>(std::floor(home_theta / dtheta + 0.5)); }

double dtheta_from_steps(int64_t steps_per_rev) {
  if (steps_per_rev <= 0 || steps_per_rev > kMaxStepsPerRev)
    throw InputError("angular steps per revolution must be a whole number from 1 to 2^40 (1099511627776), not " +
                     std::to_string(steps_per_rev));
  return 2.0 * std::numbers::pi / static_cast<double>(steps_per_rev);
}

int64_t steps_per_rev_from_dtheta(double dtheta) {
  double n = 2.0 * std::numbers::pi / dtheta;
  if (!(n <= static_cast<double>(kMaxStepsPerRev))) return 0;  // too fine (validate says so) or not a number
  double r = std::nearbyint(n);
  if (r >= 1.0 && std::abs(n - r) <= 1e-5 * r && std::abs(n - r) <= 0.05) return static_cast<int64_t>(r);
  return 0;
}

}  // namespace polarcam
