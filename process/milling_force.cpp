#include "process/milling_force.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

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
  // The rotation is sampled on a grid of M = N K steps (K per tooth pitch) and the helix is cut into slices that
  // each lag the one below by exactly one step, so that every slice of every tooth stands on the grid: a tooth's
  // force is then a sum of a slice force tabulated on the grid over a window of consecutive grid points, which
  // prefix sums give at once (the helix's lag b tan(lambda) / r is rounded to whole steps).
  const int N = c.teeth;
  const long K = std::max(1L, std::lround(kTwoPi / N / step_rad));
  const long M = N * K;
  const double h = kTwoPi / M;
  const double lag = c.axial_depth_m * std::tan(c.helix_rad) / c.radius_m;  // Eq. 5.1 over the whole depth
  const long S = lag > 0.0 ? std::max(1L, std::lround(lag / h)) : 1;
  const double db = c.axial_depth_m / static_cast<double>(S);
  // the force of one slice at grid angle m h, and its prefix sums over two turns
  std::vector<double> px(2 * M + 1, 0.0), py(2 * M + 1, 0.0), pz(2 * M + 1, 0.0);
  for (long m = 0; m < 2 * M; ++m) {
    const double phi = static_cast<double>(m % M) * h;
    double gx = 0.0, gy = 0.0, gz = 0.0;
    if (phi >= im.entry && phi <= im.exit) {
      const double sn = std::sin(phi), cs = std::cos(phi), hh = feed_per_tooth * sn;
      const double ft = c.K_t * db * hh, fr = c.K_r * db * hh;
      gx = -ft * cs - fr * sn;
      gy = ft * sn - fr * cs;
      gz = c.K_a * db * hh;
    }
    px[m + 1] = px[m] + gx;
    py[m + 1] = py[m] + gy;
    pz[m + 1] = pz[m] + gz;
  }
  const long whole = S / M, rest = S % M;  // a helix may wrap more than a turn
  // tooth j's force at the k-th rotation step: slices i = 0..S-1 at grid angle k + j K - i
  auto tooth = [&](long k, int j) {
    const long top = ((k + j * K) % M + M) % M + M;  // in [M, 2M): the window (top - rest, top] stays inside
    CutterForce f;
    f.x = whole * px[M] + px[top + 1] - px[top + 1 - rest];
    f.y = whole * py[M] + py[top + 1] - py[top + 1 - rest];
    f.z = whole * pz[M] + pz[top + 1] - pz[top + 1 - rest];
    return f;
  };
  for (long k = 0; k < K; ++k) {  // the cutter's force repeats every tooth pitch
    CutterForce f;
    for (int j = 0; j < N; ++j) {
      const CutterForce t = tooth(k, j);
      f.x += t.x;
      f.y += t.y;
      f.z += t.z;
    }
    p.resultant = std::max(p.resultant, std::hypot(f.x, f.y));
    p.normal = std::max(p.normal, std::abs(f.y));
    p.axial = std::max(p.axial, std::abs(f.z));
  }
  for (long k = 0; k < M; ++k) {
    const CutterForce t = tooth(k, 0);
    p.tooth = std::max(p.tooth, std::hypot(t.x, t.y));
  }
  return p;
}

}  // namespace polarcam::process
