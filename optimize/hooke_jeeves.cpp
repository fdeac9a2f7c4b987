#include "optimize/hooke_jeeves.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace polarcam {

HookeJeevesResult hooke_jeeves(const std::function<double(const std::vector<double>&)>& f, std::vector<double> x0,
                               const HookeJeevesOptions& o) {
  const size_t n = x0.size();
  if (o.step.size() != n || o.min_step.size() != n) throw std::invalid_argument("hooke_jeeves: one step per coordinate");
  HookeJeevesResult res;
  std::vector<double> step = o.step;
  bool exhausted = false;
  auto F = [&](const std::vector<double>& x) {
    if (res.evaluations >= o.max_evaluations) {
      exhausted = true;
      return std::numeric_limits<double>::infinity();
    }
    ++res.evaluations;
    const double v = f(x);
    return std::isnan(v) ? std::numeric_limits<double>::infinity() : v;
  };
  // exploratory moves around x (value fx); returns the value at the explored point, x updated in place
  auto explore = [&](std::vector<double>& x, double fx) {
    for (size_t i = 0; i < n && !exhausted; ++i) {
      const double xi = x[i];
      x[i] = xi + step[i];
      double v = F(x);
      if (v < fx) {
        fx = v;
        continue;
      }
      x[i] = xi - step[i];
      v = F(x);
      if (v < fx) {
        fx = v;
        continue;
      }
      x[i] = xi;
    }
    return fx;
  };

  std::vector<double> base = std::move(x0);
  double fb = F(base);
  res.bases.push_back(base);
  while (!exhausted) {
    std::vector<double> y = base;
    double fy = explore(y, fb);
    if (fy < fb) {
      for (;;) {  // pattern moves while they pay
        std::vector<double> prev = base;
        base = y;
        fb = fy;
        res.bases.push_back(base);
        std::vector<double> z(n);
        for (size_t i = 0; i < n; ++i) z[i] = base[i] + o.acceleration * (base[i] - prev[i]);
        const double fz = F(z);
        y = z;
        fy = explore(y, fz);
        if (!(fy < fb) || exhausted) break;
      }
      continue;
    }
    bool small = true;
    for (size_t i = 0; i < n; ++i) {
      step[i] *= o.reduction;
      small = small && step[i] < o.min_step[i];
    }
    ++res.reductions;
    if (small || res.reductions >= o.max_reductions) break;
  }
  res.x = base;
  res.f = fb;
  return res;
}

}  // namespace polarcam
