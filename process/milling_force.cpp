#include "process/milling_force.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "cam/error.hpp"

namespace polarcam::process {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
}  // namespace

void check_slice_cutter(const SliceCutter& c) {
  auto positive = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError(std::string("must be positive and finite"), what);
  };
  if (c.teeth < 1 || c.teeth > 100) throw InputError("must be a whole number from 1 to 100", "teeth");
  positive(c.radius_m, "radius");
  if (!(c.helix_rad >= 0.0) || !(c.helix_rad < 0.5 * kPi)) throw InputError("must be in [0, 90) deg", "helix_angle");
  positive(c.axial_depth_m, "axial_depth");
  positive(c.K_t, "K_t");
  if (!(c.K_r >= 0.0) || !std::isfinite(c.K_r)) throw InputError("must be zero or positive and finite", "K_r");
  if (!(c.K_a >= 0.0) || !std::isfinite(c.K_a)) throw InputError("must be zero or positive and finite", "K_a");
}

const char* to_string(MillingMode m) { return m == MillingMode::up ? "up" : "down"; }

double straight_engaged_angle(double radial_width, double radius) {
  if (!(radial_width > 0.0)) return 0.0;
  if (radial_width >= 2.0 * radius) return kPi;
  return std::acos(1.0 - radial_width / radius);
}

Immersion immersion_for(MillingMode mode, double engaged_angle) {
  const double psi = std::clamp(engaged_angle, 0.0, kPi);
  if (mode == MillingMode::up) return {0.0, psi};
  return {kPi - psi, kPi};
}

int slice_count(const SliceCutter& c, double max_lag_rad) {
  const double lag = c.axial_depth_m * std::tan(c.helix_rad) / c.radius_m;  // Eq. 5.1 over the whole depth
  if (!(lag > 0.0)) return 1;
  return static_cast<int>(std::clamp(std::ceil(lag / max_lag_rad), 1.0, 100000.0));
}

CutterForce slice_force(const SliceCutter& c, const Immersion& im, double feed_per_tooth, double theta, int slices,
                        int tooth) {
  CutterForce f;
  const double db = c.axial_depth_m / slices;
  const double lag_per_m = std::tan(c.helix_rad) / c.radius_m;  // Eq. 5.1: the lag of a slice per metre of height
  const double pitch = kTwoPi / c.teeth;
  const int j0 = tooth >= 0 ? tooth : 0, j1 = tooth >= 0 ? tooth + 1 : c.teeth;
  for (int i = 0; i < slices; ++i) {
    const double z = (i + 0.5) * db;
    for (int j = j0; j < j1; ++j) {
      // Eq. 5.2: the slice's angle, the tooth's tip angle less its lag
      double phi = std::fmod(theta + j * pitch - z * lag_per_m, kTwoPi);
      if (phi < 0.0) phi += kTwoPi;
      if (phi < im.entry || phi > im.exit) continue;  // Eq. 5.6: no chip outside the engagement
      const double sn = std::sin(phi), cs = std::cos(phi);
      const double h = feed_per_tooth * sn;  // the chip thickness
      const double ft = c.K_t * db * h, fr = c.K_r * db * h;
      f.x += -ft * cs - fr * sn;
      f.y += ft * sn - fr * cs;
      f.z += c.K_a * db * h;
    }
  }
  return f;
}

CutterForce mean_force(const SliceCutter& c, const Immersion& im, double feed_per_tooth) {
  const double k = c.teeth * c.axial_depth_m * feed_per_tooth / (8.0 * kPi);
  auto fx = [&](double p) { return c.K_t * std::cos(2 * p) - c.K_r * (2 * p - std::sin(2 * p)); };
  auto fy = [&](double p) { return c.K_t * (2 * p - std::sin(2 * p)) + c.K_r * std::cos(2 * p); };
  CutterForce f;
  f.x = k * (fx(im.exit) - fx(im.entry));
  f.y = k * (fy(im.exit) - fy(im.entry));
  f.z = c.teeth * c.axial_depth_m * feed_per_tooth * c.K_a / (2.0 * kPi) * (std::cos(im.entry) - std::cos(im.exit));
  return f;
}

ForcePeaks force_peaks(const SliceCutter& c, const Immersion& im, double feed_per_tooth, double step_rad) {
  ForcePeaks p;
  if (!(im.angle() > 0.0)) return p;
  const int slices = slice_count(c);
  // the cutter's force repeats every tooth period
  const int n_total = std::max(8, static_cast<int>(std::ceil(kTwoPi / c.teeth / step_rad)));
  for (int k = 0; k < n_total; ++k) {
    const CutterForce f = slice_force(c, im, feed_per_tooth, kTwoPi / c.teeth * k / n_total, slices);
    p.resultant = std::max(p.resultant, std::hypot(f.x, f.y));
    p.normal = std::max(p.normal, std::abs(f.y));
    p.axial = std::max(p.axial, std::abs(f.z));
  }
  // one tooth over a revolution
  const int n_tooth = std::max(8, static_cast<int>(std::ceil(kTwoPi / step_rad)));
  for (int k = 0; k < n_tooth; ++k) {
    const CutterForce f = slice_force(c, im, feed_per_tooth, kTwoPi * k / n_tooth, slices, 0);
    p.tooth = std::max(p.tooth, std::hypot(f.x, f.y));
  }
  return p;
}

}  // namespace polarcam::process
