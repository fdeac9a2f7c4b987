#include "machine/dynamics/largest_passing.hpp"

namespace polarcam {

LargestPassing largest_passing(const std::function<bool(double)>& pass, const BracketSpec& b) {
  LargestPassing out;
  auto test = [&](double x) {
    ++out.evaluations;
    return pass(x);
  };
  double lo, hi;
  if (test(b.x0)) {
    lo = b.x0;
    hi = b.grow(b.x0);
    while (true) {
      if (hi >= b.cap) {
        if (test(b.cap)) {
          out.x = b.cap;
          out.capped = true;
          return out;
        }
        hi = b.cap;
        break;
      }
      if (!test(hi)) break;
      lo = hi;
      hi = b.grow(hi);
    }
  } else if (b.down_geometric) {
    hi = b.x0;
    lo = 0.8 * b.x0;
    while (!test(lo)) {
      hi = lo;
      lo *= 0.8;
      if (lo < b.x_min) return out;
    }
  } else {
    if (!test(b.x_min)) return out;
    lo = b.x_min;
    hi = b.x0;
  }
  while (hi - lo > b.rel_tol * (b.tol_of_top ? hi : lo)) {
    const double mid = 0.5 * (lo + hi);
    if (test(mid))
      lo = mid;
    else
      hi = mid;
  }
  out.x = lo;
  return out;
}

LargestPassing confirmed_largest_passing(const std::function<bool(double)>& quick,
                                         const std::function<bool(double)>& exact, const BracketSpec& b) {
  LargestPassing q = largest_passing(quick, b);
  int checks = 0;
  auto check = [&](double x) {
    ++checks;
    return exact(x);
  };
  if (q.x && check(*q.x) && (q.capped || !check(*q.x * (1.0 + 2.0 * b.rel_tol)))) {
    q.evaluations += checks;
    return q;
  }
  LargestPassing e = largest_passing(exact, b);
  e.evaluations += q.evaluations + checks;
  return e;
}

}  // namespace polarcam
