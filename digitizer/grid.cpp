#include "digitizer/grid.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "cam/error.hpp"

namespace polarcam {

void Grid::validate() const {
  if (!(dr > 0.0) || !std::isfinite(dr)) throw InputError("the radial resolution must be a positive length");
  if (!(dtheta > 0.0) || !std::isfinite(dtheta)) throw InputError("the angular resolution must be a positive angle");
  if (dtheta > std::numbers::pi / 4) throw InputError("the angular resolution is coarser than an eighth of a turn");
  if (!(r_min >= 0.0) || !std::isfinite(r_min)) throw InputError("r_min must be zero or a positive length");
  if (r_max && (!std::isfinite(*r_max) || !(*r_max > r_min))) throw InputError("r_max must be greater than r_min");
  if (theta_min.has_value() != theta_max.has_value())
    throw InputError("give both theta_min and theta_max, or neither (unlimited rotation)");
  if (theta_min && (!std::isfinite(*theta_min) || !std::isfinite(*theta_max) || !(*theta_max > *theta_min)))
    throw InputError("theta_max must be greater than theta_min");
  if (!std::isfinite(home_r) || !std::isfinite(home_theta)) throw InputError("the home position must be finite");
  if (r_max && (*r_max / dr > 4e15)) throw InputError("the radial resolution is too fine for the work area");
}

int64_t Grid::home_n() const { return static_cast<int64_t>(std::floor(home_r / dr + 0.5)); }
int64_t Grid::home_m() const { return static_cast<int64_t>(std::floor(home_theta / dtheta + 0.5)); }

double dtheta_from_steps(int64_t steps_per_rev) {
  if (steps_per_rev <= 0) throw InputError("angular steps per revolution must be a positive whole number");
  return 2.0 * std::numbers::pi / static_cast<double>(steps_per_rev);
}

int64_t steps_per_rev_from_dtheta(double dtheta) {
  double n = 2.0 * std::numbers::pi / dtheta;
  double r = std::nearbyint(n);
  if (r >= 1.0 && std::abs(n - r) <= 1e-5 * r && std::abs(n - r) <= 0.05) return static_cast<int64_t>(r);
  return 0;
}

}  // namespace polarcam
