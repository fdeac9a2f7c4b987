#include "machine/pulse_speed.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace polarcam {

PulseSpeedMeter::PulseSpeedMeter(double step0_m, double step1_m) : len_{step0_m, step1_m} {}

void PulseSpeedMeter::step(int axis, int dir, int64_t t_ns) {
  t_[axis & 1].push_back(t_ns);
  d_[axis & 1].push_back(dir > 0 ? 1 : 0);
}

std::vector<double> PulseSpeedMeter::interval_speeds(int a) const {
  const std::vector<int64_t>& T = t_[a];
  const std::vector<uint8_t>& D = d_[a];
  const size_t n = T.size() < 2 ? 0 : T.size() - 1;
  std::vector<double> raw(n), v(n);
  for (size_t i = 0; i < n; ++i) raw[i] = len_[a] * 1e9 / static_cast<double>(std::max<int64_t>(T[i + 1] - T[i], 1));
  for (size_t i = 0; i < n; ++i) {
    v[i] = raw[i];
    if (D[i] != D[i + 1]) {  // the axis turned round: no faster than just before or just after
      double cap = 0.0;
      if (i > 0) cap = raw[i - 1];
      if (i + 1 < n) cap = std::max(cap, raw[i + 1]);
      v[i] = std::min(raw[i], cap);
    }
  }
  return v;
}

PulseSpeedStats PulseSpeedMeter::stats(double nominal) const {
  PulseSpeedStats st;
  st.nominal_mps = nominal;
  double sw = 0.0, swv = 0.0, swd = 0.0;
  double vmin = std::numeric_limits<double>::infinity(), vmax = 0.0;
  const std::vector<double> speed[2] = {interval_speeds(0), interval_speeds(1)};
  for (int a = 0; a < 2; ++a) {
    const std::vector<int64_t>& A = t_[a];
    const std::vector<int64_t>& B = t_[1 - a];
    const std::vector<double>& VA = speed[a];
    const std::vector<double>& VB = speed[1 - a];
    const size_t nb = B.size();
    size_t j = 0;
    for (size_t i = 0; i + 1 < A.size(); ++i) {
      const int64_t dt = std::max<int64_t>(A[i + 1] - A[i], 1);
      const int64_t m2 = A[i] + A[i + 1];  // twice the midpoint: exact in integers
      while (j + 1 < nb && 2 * B[j + 1] <= m2) ++j;
      double vb = 0.0;
      if (nb >= 2) {
        if (m2 < 2 * B[0]) {  // before the other axis's first pulse
          if (m2 >= 2 * (B[0] - (B[1] - B[0]))) vb = VB.front();
        } else if (j + 1 < nb) {  // B[j] <= midpoint < B[j + 1]
          vb = VB[j];
        } else {  // after its last pulse
          if (m2 <= 2 * (B[nb - 1] + (B[nb - 1] - B[nb - 2]))) vb = VB.back();
        }
      }
      const double v = std::hypot(VA[i], vb), w = static_cast<double>(dt);
      vmin = std::min(vmin, v);
      vmax = std::max(vmax, v);
      sw += w;
      swv += w * v;
      swd += w * (v - nominal) * (v - nominal);
      ++st.samples;
    }
  }
  if (st.samples == 0) return st;
  st.min_mps = vmin;
  st.max_mps = vmax;
  st.mean_mps = swv / sw;
  st.rms_dev_mps = std::sqrt(swd / sw);
  return st;
}

}  // namespace polarcam
