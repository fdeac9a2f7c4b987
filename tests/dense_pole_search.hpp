#pragma once
// An independent check of the pole optimizers: the objective evaluated on a dense grid of poles over a search box,
// through the public evaluate_poles, and the least value found.
#include <cstdlib>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "optimize/placement.hpp"

namespace polarcam::test {

// The long variants of the dense-search tests run when POLARCAM_LONG_TESTS=1.
[[maybe_unused]] inline bool long_tests() {
  const char* e = std::getenv("POLARCAM_LONG_TESTS");
  return e && std::string(e) == "1";
}

struct DenseBest {
  double value = std::numeric_limits<double>::infinity();
  Vec2 pole{};
};

// n x n poles over the box, corners included: the least `objective` (+inf where it does not apply).
inline DenseBest dense_search(const PoleProblem& p, const SearchBox& b, int n,
                              const std::function<double(const PoleValue&)>& objective) {
  std::vector<Vec2> poles;
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix)
      poles.push_back({b.x0 + (b.x1 - b.x0) * ix / (n - 1), b.y0 + (b.y1 - b.y0) * iy / (n - 1)});
  const std::vector<PoleValue> v = evaluate_poles(p, poles, 2);
  DenseBest best;
  for (size_t i = 0; i < v.size(); ++i)
    if (const double f = objective(v[i]); f < best.value) best = {f, poles[i]};
  return best;
}

}  // namespace polarcam::test
