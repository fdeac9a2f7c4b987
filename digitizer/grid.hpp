#pragma once
// The machine grid the digitizer steps on: radial resolution DeltaR, angular resolution DeltaTheta (and the
// whole number of steps per revolution when there is one), the work area and the home position.
// Node (n, m) is the point r = n DeltaR, theta = m DeltaTheta about the machine pole; theta is unwrapped, so
// m keeps counting past a full turn.
#include <cstdint>
#include <optional>

namespace polarcam {

// What a tape and the step arithmetic can represent: at most 2^40 angular steps per revolution, resolutions no
// finer than 1e-12 m and 2 pi / 2^40 rad, and node indices (work area and home over the resolution) within 2^50,
// so that sums and scalings of node indices stay far from 64-bit overflow.
inline constexpr int64_t kMaxStepsPerRev = int64_t{1} << 40;
inline constexpr double kMinRadialResolution = 1e-12;  // m
inline constexpr double kMaxNodeIndex = 1125899906842624.0;  // 2^50

struct Grid {
  double dr = 0.0;                // m per radial step
  double dtheta = 0.0;            // rad per angular step
  int64_t steps_per_rev = 0;      // angular steps per revolution when 2 pi / dtheta is a whole number, else 0
  double r_min = 0.0;             // m
  std::optional<double> r_max;    // m
  std::optional<double> theta_min, theta_max;  // rad; both or neither
  double home_r = 0.0, home_theta = 0.0;       // machine home position (m, rad)

  // Throws InputError when the grid is not usable.
  void validate() const;
  int64_t home_n() const;
  int64_t home_m() const;
};

// Angular resolution for a whole number of steps per revolution.
double dtheta_from_steps(int64_t steps_per_rev);
// Steps per revolution N when 2 pi / dtheta is within 1e-5 relative (and 0.05 steps) of a whole number, else 0.
// The thesis's "3.927e-4 rad" is 2 pi / 16000 rounded to four figures; callers then use dtheta = 2 pi / N.
int64_t steps_per_rev_from_dtheta(double dtheta);

}  // namespace polarcam
