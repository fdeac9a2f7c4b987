#include "process/cutting_force.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "cam/error.hpp"

namespace polarcam::process {
namespace {

void positive(double v, const char* what) {
  if (!(std::isfinite(v) && v > 0.0)) throw InputError("must be positive and finite", what);
}

}  // namespace

double tooth_period(int teeth, double spindle_speed_rad_s) {
  if (teeth < 1) throw InputError("must be a whole number of at least 1", "teeth");
  positive(spindle_speed_rad_s, "spindle speed");
  const double tau = 2.0 * std::numbers::pi / (teeth * spindle_speed_rad_s);
  if (!(std::isfinite(tau) && tau > 0.0)) throw InputError("gives no finite tooth period", "spindle speed");
  return tau;
}

double LumpedForceModel::force(double b, double a, const std::function<double(double)>& v, double t) const {
  return C(b, a) * v(t - tau);
}

LumpedForceModel calibrate_lumped_model(double F, double f_t, double b, double a, double tau) {
  positive(F, "force");
  positive(f_t, "feed per tooth");
  positive(b, "axial depth");
  positive(a, "radial depth");
  positive(tau, "tooth period");
  const double v = f_t / tau;
  const double C = F / v;
  const double K = C / (b * a);
  if (!(std::isfinite(K) && K > 0.0)) throw InputError("the cut gives no finite positive K (C / (b a))", "force");
  return {K, tau};
}

LumpedForceModel lumped_model_from_specific_force(double k, double tau) {
  positive(k, "specific force");
  positive(tau, "tooth period");
  if (!std::isfinite(k * tau)) throw InputError("gives no finite K (k tau)", "specific force");
  return {k * tau, tau};
}

std::vector<double> lumped_forces(const LumpedForceModel& m, const std::vector<double>& axial_depths, double a,
                                  double v) {
  positive(a, "radial depth");
  if (!(std::isfinite(v) && v >= 0.0)) throw InputError("must be zero or positive and finite", "feed speed");
  std::vector<double> F;
  for (double b : axial_depths) {
    positive(b, "axial depth");
    F.push_back(m.C(b, a) * v);
    if (!std::isfinite(F.back())) throw InputError("gives no finite force", "axial depth");
  }
  return F;
}

}  // namespace polarcam::process
