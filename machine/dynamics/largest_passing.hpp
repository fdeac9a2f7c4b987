#pragma once
// The largest x at which a monotone test passes, by bracketing and bisection: the one search behind the verdict's
// passing speed (machine/dynamics/verdict) and the capacity limits (optimize/capacity).
#include <functional>
#include <optional>

namespace polarcam {

struct BracketSpec {
  double x0 = 1.0;     // where the search starts
  double x_min = 0.0;  // below this nothing is tried: no passing x
  double cap = 0.0;    // above this nothing is tried: cap itself is the answer when it passes (`capped`)
  std::function<double(double)> grow;  // the next x upwards while x passes (e.g. 1.25 x)
  double rel_tol = 1e-4;               // bisection until the bracket is rel_tol of its bottom (or top) wide
  bool tol_of_top = false;             // rel_tol relative to the bracket's top instead of its bottom
  bool down_geometric = true;  // x0 fails: step down by 0.8 x until one passes (else try x_min at once)
};

struct LargestPassing {
  std::optional<double> x;  // the largest passing x found (it passes); nullopt when nothing down to x_min passes
  bool capped = false;      // cap still passes
  int evaluations = 0;      // calls of the test
};

LargestPassing largest_passing(const std::function<bool(double)>& pass, const BracketSpec& b);

// The largest x passing `exact`, searched with `quick` (a cheaper test that nearly always agrees with it, such as a
// torque analysis at the searches' sampling) and confirmed with `exact`: quick's answer is taken when it passes
// `exact` and, unless capped, x (1 + 2 rel_tol), beyond the search's last bracket, fails `exact`; otherwise the
// search runs again with `exact`. `evaluations` counts the calls of both tests.
LargestPassing confirmed_largest_passing(const std::function<bool(double)>& quick,
                                         const std::function<bool(double)>& exact, const BracketSpec& b);

}  // namespace polarcam
