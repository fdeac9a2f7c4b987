#pragma once
// The thesis's machine grid (0.001 in radially, 16 000 steps a turn), or `finer` times finer on both axes: the
// grids the benchmarks run on.
#include <cstdint>

#include "digitizer/grid.hpp"

namespace polarcam::bench {

inline Grid thesis_grid(double finer) {
  Grid g;
  g.dr = 0.0254e-3 / finer;
  g.steps_per_rev = static_cast<int64_t>(16000 * finer);
  g.dtheta = dtheta_from_steps(g.steps_per_rev);
  return g;
}

}  // namespace polarcam::bench
