#include "process/simulate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "cam/error.hpp"

namespace polarcam::process {
namespace {

using State = std::array<double, 4>;  // x_m, v_m, x_w, v_w

State derivative(const TwoMassStructure& p, const State& y, double force) {
  const double rel = p.C_w * (y[3] - y[1]) + p.K_w * (y[2] - y[0]);  // the workpiece's pull on the machine
  return {y[1], (rel - p.C_m * y[1] - p.K_m * y[0]) / p.M_m, y[3], (force - rel) / p.M_w};
}

}  // namespace

SimulationResult simulate_chatter(const TwoMassStructure& p, const Cut& c, double kc, const SimulationOptions& o) {
  return simulate_chatter(p, c, kc, o, nullptr);
}

SimulationResult simulate_chatter(const TwoMassStructure& p, const Cut& c, double kc, const SimulationOptions& o,
                                  ToolMotion* tool) {
  check(p, c);
  if (!(std::isfinite(kc) && kc >= 0.0)) throw InputError("must be a cutting gain of 0 or more (N/m)", "--simulate");
  const double T = c.revolution_period, mu = c.overlap, U0 = c.depth;
  const double w_top = undamped_frequencies(p)[1];
  long n = o.steps_per_revolution;
  const long spr = std::max(1, o.samples_per_revolution);
  if (n <= 0) {
    n = std::max(16L, static_cast<long>(std::ceil(T * w_top / 0.05)));
    n = (n + spr - 1) / spr * spr;  // a whole number of steps between kept samples
  }
  const double duration = o.duration > 0.0 ? o.duration : 40.0 * T;
  const double revs = duration / T;
  if (!(revs >= 1.0) || revs * static_cast<double>(n) > 5e8)
    throw InputError("must be at least one revolution and at most 5e8 integration steps (" + std::to_string(n) +
                         " per revolution)",
                     "--duration");
  const long total = static_cast<long>(std::llround(std::ceil(revs * static_cast<double>(n))));
  const double h = T / static_cast<double>(n);
  const long every = std::max(1L, n / spr);

  SimulationResult r;
  r.step = h;
  // equilibrium: X_w = F G(0) with F = K_c (U0 - (1 - mu) X_w), G(0) = 1/K_m + 1/K_w
  const double g0 = 1.0 / p.K_m + 1.0 / p.K_w;
  r.static_displacement = kc * U0 * g0 / (1.0 + kc * (1.0 - mu) * g0);

  // one revolution of X_w and V_w behind the present (ring buffer of n + 1 stored steps)
  std::vector<double> hx(static_cast<size_t>(n + 1), 0.0), hv(static_cast<size_t>(n + 1), 0.0);
  auto delayed = [&](long k, double frac) {
    // X_w at (k + frac) h - T: between stored steps k - n and k - n + 1 (zero before the cut started)
    const long i = k - n;
    auto at = [&](long j, double& x, double& v) {
      if (j < 0) {
        x = v = 0.0;
        return;
      }
      const size_t s = static_cast<size_t>(j % (n + 1));
      x = hx[s];
      v = hv[s];
    };
    double x0, v0, x1, v1;
    at(i, x0, v0);
    if (frac == 0.0) return x0;
    at(i + 1, x1, v1);
    const double t = frac, t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * x0 + (t3 - 2 * t2 + t) * h * v0 + (-2 * t3 + 3 * t2) * x1 + (t3 - t2) * h * v1;
  };
  State y{0.0, 0.0, 0.0, 0.0};
  // the tool's displacement now and one revolution ago: constant over each (sub-)step, 0 without a tool
  double xt = 0.0, xtd = 0.0;
  auto force_at = [&](const State& s, long k, double frac) {
    return kc * (U0 - (s[2] - xt) + mu * (delayed(k, frac) - xtd));
  };
  auto store = [&](long k, const State& s) {
    const size_t i = static_cast<size_t>(k % (n + 1));
    hx[i] = s[2];
    hv[i] = s[3];
  };
  // one classical Runge-Kutta step over the fraction [fa, fb] of step k (the whole step: fa = 0, fb = 1)
  auto rk4 = [&](long k, double fa, double fb) {
    const double hs = (fb - fa) * h, fm = fa + 0.5 * (fb - fa);
    const State k1 = derivative(p, y, force_at(y, k, fa));
    State y2, y3, y4;
    for (int i = 0; i < 4; ++i) y2[i] = y[i] + 0.5 * hs * k1[i];
    const State k2 = derivative(p, y2, force_at(y2, k, fm));
    for (int i = 0; i < 4; ++i) y3[i] = y[i] + 0.5 * hs * k2[i];
    const State k3 = derivative(p, y3, force_at(y3, k, fm));
    for (int i = 0; i < 4; ++i) y4[i] = y[i] + hs * k3[i];
    const State k4 = derivative(p, y4, fb == 1.0 ? force_at(y4, k + 1, 0.0) : force_at(y4, k, fb));
    for (int i = 0; i < 4; ++i) y[i] += hs / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  };
  // with a tool: the step split at every event and every move one revolution back, X_t set for each piece
  constexpr double kInf = std::numeric_limits<double>::infinity(), kEps = 1e-9;
  double done_now = -kInf, done_delayed = -kInf;  // the last event handled, the last move handled one revolution back
  auto tool_step = [&](long k) {
    const double t0 = static_cast<double>(k) * h;
    double fa = 0.0;
    auto piece = [&](double fb) {
      const double tm = t0 + 0.5 * (fa + fb) * h;
      xt = tool->position(tm);
      xtd = tool->position(tm - T);
      rk4(k, fa, fb);
      fa = fb;
    };
    for (;;) {
      const double e1 = tool->next_event(done_now);
      const double m2 = mu > 0.0 ? tool->next_move(done_delayed) : kInf;
      const double e = std::min(e1, m2 + T), fe = (e - t0) / h;
      if (!(fe <= 1.0 + kEps)) break;
      if (fe >= 1.0 - kEps) {
        if (fa < 1.0) piece(1.0);
      } else if (fe - fa > kEps) {
        piece(fe);
      }
      if (e1 <= e) {
        const double force = fa == 1.0 ? force_at(y, k + 1, 0.0) : force_at(y, k, fa);
        tool->event(e1, force, y[2]);
        done_now = e1;
      }
      if (m2 + T <= e) done_delayed = m2;
    }
    if (fa < 1.0) piece(1.0);
    xt = tool->position(t0 + h);
    xtd = tool->position(t0 + h - T);
  };
  store(0, y);
  double amp = 0.0, prev_dev = -r.static_displacement, first = -1.0, last = -1.0;
  double lo = 0.0, hi = 0.0, dlo = 0.0, dhi = 0.0;  // X_w and X_w - X_t over the revolution
  int crossings = 0;
  r.samples.push_back({0.0, y[0], y[2], force_at(y, 0, 0.0), 0.0});
  for (long k = 0; k < total; ++k) {
    if (tool)
      tool_step(k);
    else
      rk4(k, 0.0, 1.0);
    if (!std::isfinite(y[2]) || std::abs(y[2]) > 1e100)
      throw InputError("the simulated vibration overflows before the end: give a shorter --duration or a smaller gain",
                       "--simulate");
    store(k + 1, y);
    amp = std::max(amp, std::abs(y[2] - r.static_displacement));
    lo = std::min(lo, y[2]);
    hi = std::max(hi, y[2]);
    dlo = std::min(dlo, y[2] - xt);
    dhi = std::max(dhi, y[2] - xt);
    if ((k + 1) % n == 0) {
      r.revolution_amplitude.push_back(amp);
      r.revolution_half_range.push_back(0.5 * (hi - lo));
      r.revolution_relative_half_range.push_back(0.5 * (dhi - dlo));
      amp = 0.0;
      lo = hi = y[2];
      dlo = dhi = y[2] - xt;
    }
    if (k >= total * 3 / 4) {  // zero crossings of X_w about the equilibrium over the last quarter
      const double u = prev_dev, v = y[2] - r.static_displacement;
      if ((u < 0.0) != (v < 0.0)) {
        const double t = static_cast<double>(k) * h + h * u / (u - v);
        if (first < 0.0) first = t;
        last = t;
        ++crossings;
      }
    }
    prev_dev = y[2] - r.static_displacement;
    if ((k + 1) % every == 0 || k + 1 == total)
      r.samples.push_back({static_cast<double>(k + 1) * h, y[0], y[2], force_at(y, k + 1, 0.0), xt});
  }
  const auto& a = r.revolution_amplitude;
  if (a.size() >= 3 && a[1] > 0.0)
    r.growth_per_revolution = std::pow(a.back() / a[1], 1.0 / static_cast<double>(a.size() - 2));
  if (crossings >= 2) r.frequency = std::numbers::pi * (crossings - 1) / (last - first);
  return r;
}

}  // namespace polarcam::process
