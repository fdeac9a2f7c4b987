#include "metrics/pulse_speed.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "cam/error.hpp"
#include "digitizer/replay.hpp"

namespace polarcam {
namespace pulse_speed_detail {

namespace {
double raw(const Pulse& a, const Pulse& b) {
  const int64_t dt = std::max<int64_t>(b.t_ns - a.t_ns, 1);
  return 0.5 * (a.length_m + b.length_m) * 1e9 / static_cast<double>(dt);
}
}  // namespace

Intervals::Intervals(PulseSource& s) : s_(s) {
  has_a_ = read(a_);
  has_b_ = has_a_ && read(b_);
  has_c_ = has_b_ && read(c_);
}

bool Intervals::next(Interval& iv) {
  if (!has_a_ || !has_b_) return false;
  iv.t0 = a_.t_ns;
  iv.t1 = b_.t_ns;
  iv.v = raw(a_, b_);
  if (a_.dir != b_.dir) {  // a turnaround: no faster than the neighbouring intervals
    double cap = 0.0;
    if (has_prev_) cap = raw(prev_, a_);
    if (has_c_) cap = std::max(cap, raw(b_, c_));
    iv.v = std::min(iv.v, cap);
  }
  prev_ = a_;
  has_prev_ = true;
  a_ = b_;
  has_b_ = has_c_;
  if (has_c_) {
    b_ = c_;
    has_c_ = read(c_);
  }
  return true;
}

void add_samples(PulseSource& a, PulseSource& b, double nominal, Sums& sums, SpeedTrace* trace) {
  Intervals A(a), B(b);
  Interval ib, first, last, ia;
  const bool have_b = B.next(ib);
  if (have_b) first = last = ib;
  while (A.next(ia)) {
    const int64_t m2 = ia.t0 + ia.t1;  // twice the midpoint: exact in integers
    while (have_b && 2 * ib.t1 <= m2) {
      Interval nx;
      if (!B.next(nx)) break;
      ib = last = nx;
    }
    double vb = 0.0;
    if (have_b) {
      if (m2 < 2 * first.t0) {  // before the other axis's first pulse: its first interval, if within one
        if (m2 >= 2 * (first.t0 - (first.t1 - first.t0))) vb = first.v;
      } else if (m2 < 2 * ib.t1) {  // ib.t0 <= midpoint < ib.t1
        vb = ib.v;
      } else if (m2 <= 2 * (last.t1 + (last.t1 - last.t0))) {  // after its last pulse, within one interval
        vb = last.v;
      }
    }
    const double v = std::hypot(ia.v, vb), w = static_cast<double>(std::max<int64_t>(ia.t1 - ia.t0, 1));
    if (sums.n == 0) sums.vmin = sums.vmax = v;
    sums.vmin = std::min(sums.vmin, v);
    sums.vmax = std::max(sums.vmax, v);
    sums.sw += w;
    sums.swv += w * v;
    sums.swd += w * (v - nominal) * (v - nominal);
    ++sums.n;
    if (trace) trace->add(static_cast<double>(m2) * 0.5e-9, v, w);
  }
}

PulseSpeedStats finish(const Sums& s, double nominal) {
  PulseSpeedStats st;
  st.nominal_mps = nominal;
  st.samples = s.n;
  if (s.n == 0) return st;
  st.min_mps = s.vmin;
  st.max_mps = s.vmax;
  st.mean_mps = s.swv / s.sw;
  st.rms_dev_mps = std::sqrt(s.swd / s.sw);
  return st;
}

}  // namespace pulse_speed_detail

SpeedTrace::SpeedTrace(int bins, double t_end) : t_end_s(t_end) {
  const size_t n = static_cast<size_t>(std::max(bins, 1));
  vmin.assign(n, std::numeric_limits<double>::quiet_NaN());
  vmax.assign(n, std::numeric_limits<double>::quiet_NaN());
  sw.assign(n, 0.0);
  swv.assign(n, 0.0);
}

void SpeedTrace::add(double t_s, double v, double w) {
  const int n = bins();
  int i = t_end_s > 0.0 ? static_cast<int>(std::floor(t_s / t_end_s * n)) : 0;
  i = std::clamp(i, 0, n - 1);
  const size_t k = static_cast<size_t>(i);
  if (!(sw[k] > 0.0)) vmin[k] = vmax[k] = v;
  vmin[k] = std::min(vmin[k], v);
  vmax[k] = std::max(vmax[k], v);
  sw[k] += w;
  swv[k] += w * v;
}

double SpeedTrace::mean(int i) const {
  const size_t k = static_cast<size_t>(i);
  return sw[k] > 0.0 ? swv[k] / sw[k] : std::numeric_limits<double>::quiet_NaN();
}

namespace {

class VectorSource final : public PulseSource {
 public:
  explicit VectorSource(const std::vector<Pulse>& v) : v_(v) {}
  bool next(Pulse& p) override {
    if (i_ == v_.size()) return false;
    p = v_[i_++];
    return true;
  }

 private:
  const std::vector<Pulse>& v_;
  size_t i_ = 0;
};

// One axis of a tape, read through its own reader.
class TapeSource final : public PulseSource {
 public:
  TapeSource(const std::string& path, int axis, double speed_scale) : rd_(path), rp_(rd_), axis_(axis), k_(speed_scale) {
    const TapeHeader& h = rd_.header();
    polar_ = h.axes == TapeAxes::polar;
    res_[0] = h.res[0];
    res_[1] = h.res[1];
    ps_per_tick_ = h.tick_ps;
  }
  bool next(Pulse& p) override {
    MachineStep s;
    while (rp_.next(s)) {
      if (s.axis != axis_) continue;
      p.t_ns = ps_per_tick_ == 1000 && k_ == 1.0
                   ? static_cast<int64_t>(s.t_ticks)
                   : std::llround(static_cast<double>(s.t_ticks) * static_cast<double>(ps_per_tick_) * 1e-3 / k_);
      p.dir = s.dir;
      // an angular step moves the tool r DeltaTheta, r = n DeltaR (n is not changed by angular steps)
      p.length_m = (polar_ && axis_ == 1) ? static_cast<double>(std::llabs(s.node[0])) * res_[0] * res_[1] : res_[axis_];
      return true;
    }
    return false;
  }

 private:
  TapeReader rd_;
  TapeReplay rp_;
  int axis_;
  double k_ = 1.0;
  bool polar_ = false;
  double res_[2] = {0, 0};
  uint64_t ps_per_tick_ = 1000;
};

}  // namespace

PulseSpeedStats measure_tape_speed(const std::string& tape_path, double nominal_mps, double speed_scale,
                                   SpeedTrace* trace) {
  if (!(speed_scale > 0.0) || !std::isfinite(speed_scale)) throw InputError("a speed scale must be a number above zero");
  return measure_pulse_speed([&](int axis) { return std::make_unique<TapeSource>(tape_path, axis, speed_scale); },
                             nominal_mps, trace);
}

PulseSpeedMeter::PulseSpeedMeter(double step0_m, double step1_m) : len_{step0_m, step1_m} {}

void PulseSpeedMeter::step(int axis, int dir, int64_t t_ns) {
  p_[axis & 1].push_back(Pulse{t_ns, dir > 0 ? 1 : -1, len_[axis & 1]});
}

PulseSpeedStats PulseSpeedMeter::stats(double nominal_mps) const {
  return measure_pulse_speed([&](int axis) { return std::make_unique<VectorSource>(p_[axis]); }, nominal_mps);
}

}  // namespace polarcam
