#include "process/describing_function.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "cam/error.hpp"

namespace polarcam::process {

DualInputGains quantiser_error_didf(double A, double B, double D, double H) {
  if (!(std::isfinite(A) && A > 0.0)) throw InputError("must be a positive amplitude", "A");
  if (!std::isfinite(B)) throw InputError("must be a finite level", "B");
  if (!(std::isfinite(D) && D > 0.0)) throw InputError("must be a positive output step", "D");
  if (!(std::isfinite(H) && H > 0.0)) throw InputError("must be a positive switching interval", "H");
  if ((A + std::abs(B)) / H > 1e7) throw InputError("spans more than 1e7 switching levels", "A");
  constexpr double pi = std::numbers::pi;
  auto p = [](double d) { return d <= -1.0 ? -0.5 : d >= 1.0 ? 0.5 : std::asin(d) / pi; };
  auto q = [](double d) { return std::abs(d) >= 1.0 ? 0.0 : 2.0 / pi * std::sqrt(1.0 - d * d); };
  double sum_p = 0.0, sum_q = 0.0, slope = 0.0;
  // levels beyond A + |B| are never crossed: p gives 1/2 - 1/2 and q gives 0
  for (long i = 1;; ++i) {
    const double c = (2.0 * static_cast<double>(i) - 1.0) / 2.0 * H;
    if (c - std::abs(B) >= A) break;
    const double g1 = (c + B) / A, g2 = (c - B) / A;
    sum_p += p(g1) - p(g2);
    sum_q += q(g1) + q(g2);
    // d/dB of p(g1) - p(g2) at B = 0: 2 / (pi A sqrt(1 - (c / A)^2))
    const double d = c / A;
    slope += d < 1.0 ? 2.0 / (pi * A * std::sqrt(1.0 - d * d)) : std::numeric_limits<double>::infinity();
  }
  DualInputGains g;
  g.dc = B != 0.0 ? 1.0 - D / B * sum_p : 1.0 - D * slope;
  g.ac = 1.0 - D / A * sum_q;
  return g;
}

}  // namespace polarcam::process
