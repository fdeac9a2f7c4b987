#include "process/stability.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>

#include "cam/error.hpp"

namespace polarcam::process {
namespace {

// The frequencies searched: an even grid fine against H's period and the frequency range, refined geometrically
// around every mode (a lightly damped mode turns G's phase by pi within a few sigma of omega_d).
std::vector<double> frequency_grid(const TransferFunction& g, double period, double w_max, int per_period) {
  const std::vector<Mode> ms = modes(g);
  double h = w_max / 20000.0;
  if (period > 0.0) h = std::min(h, 2.0 * std::numbers::pi / period / per_period);
  std::vector<double> w;
  const auto n = static_cast<long>(std::ceil(w_max / h));
  w.reserve(static_cast<size_t>(n) + 400 * ms.size());
  for (long i = 1; i <= n; ++i) w.push_back(w_max * static_cast<double>(i) / static_cast<double>(n));
  for (const Mode& m : ms) {
    const double step0 = std::max(m.sigma * 0.01, m.omega_d * 1e-12);
    for (double d = step0; d < 64.0 * h && d < 0.5 * m.omega_d; d *= 1.08) {
      if (m.omega_d + d < w_max) w.push_back(m.omega_d + d);
      w.push_back(m.omega_d - d);
    }
    if (m.omega_d < w_max) w.push_back(m.omega_d);
  }
  std::sort(w.begin(), w.end());
  w.erase(std::unique(w.begin(), w.end()), w.end());
  return w;
}

double highest_mode(const TransferFunction& g) {
  double top = 0.0;
  for (const std::complex<double> p : poles(g)) top = std::max(top, std::abs(p));
  return top;
}

// A zero of f between a and b (f(a), f(b) of opposite signs or zero): bisection to the last bits.
template <class F>
double bracket_zero(F&& f, double a, double b, double fa) {
  for (int i = 0; i < 200 && b - a > 4.0 * std::numeric_limits<double>::epsilon() * b; ++i) {
    const double m = 0.5 * (a + b), fm = f(m);
    if (fm == 0.0) return m;
    if ((fm < 0.0) == (fa < 0.0)) {
      a = m;
      fa = fm;
    } else {
      b = m;
    }
  }
  return 0.5 * (a + b);
}

struct Crossings {
  std::optional<double> gain;
  double w = 0.0;
  int count = 0;
};

Crossings scan(const TransferFunction& g, double mu, double T, double w_hi, int per_period) {
  auto L = [&](double w) { return regeneration(mu, T, w) * g.at(w); };
  const std::vector<double> grid = frequency_grid(g, T, w_hi, per_period);
  // brackets of a sign change of Im L where Re L < 0, with a first estimate of the gain by interpolation
  struct Bracket {
    double a, b, fa, estimate;
  };
  std::vector<Bracket> br;
  std::complex<double> prev = L(grid.front());
  for (size_t i = 1; i < grid.size(); ++i) {
    const std::complex<double> cur = L(grid[i]);
    if ((prev.imag() < 0.0) != (cur.imag() < 0.0) || cur.imag() == 0.0) {
      const double t = prev.imag() == cur.imag() ? 0.5 : prev.imag() / (prev.imag() - cur.imag());
      const double re = prev.real() + t * (cur.real() - prev.real());
      if (re < 0.0 || prev.real() < 0.0 || cur.real() < 0.0)
        br.push_back({grid[i - 1], grid[i], prev.imag(), re < 0.0 ? -1.0 / re : std::numeric_limits<double>::infinity()});
    }
    prev = cur;
  }
  Crossings out;
  double best_estimate = std::numeric_limits<double>::infinity();
  for (const Bracket& b : br) best_estimate = std::min(best_estimate, b.estimate);
  for (const Bracket& b : br) {
    // the interpolated estimate is close on this grid; brackets far above the best are not refined
    if (std::isfinite(best_estimate) && b.estimate > 4.0 * best_estimate) {
      ++out.count;
      continue;
    }
    const double w = b.fa == 0.0 ? b.a : bracket_zero([&](double x) { return L(x).imag(); }, b.a, b.b, b.fa);
    const double re = L(w).real();
    if (!(re < 0.0)) continue;
    ++out.count;
    const double k = -1.0 / re;
    if (!out.gain || k < *out.gain) {
      out.gain = k;
      out.w = w;
    }
  }
  return out;
}

}  // namespace

NyquistLimit nyquist_limit(const TransferFunction& g, double mu, double T, const StabilityOptions& o) {
  const double top = highest_mode(g);
  double w_hi = o.w_max > 0.0 ? o.w_max : 4.0 * top;
  NyquistLimit out;
  for (int round = 0; round < 8; ++round) {
    const Crossings c = scan(g, mu, T, w_hi, o.samples_per_period);
    out.crossings = c.count;
    if (c.gain) {
      out.critical_gain = c.gain;
      out.chatter_frequency = c.w;
    }
    if (o.w_max > 0.0) break;
    // beyond w_hi (above every mode, |G| falling) a crossing needs K_c >= 1 / ((1 + mu) |G|)
    const double bound = 1.0 / ((1.0 + mu) * std::abs(g.at(w_hi)));
    if (out.critical_gain && bound > *out.critical_gain) break;
    if (!out.critical_gain && mu == 0.0) break;
    w_hi *= 2.0;
  }
  return out;
}

SimpleLimit simple_criterion(const TransferFunction& g, double mu, const StabilityOptions& o) {
  const double top = highest_mode(g);
  const double w_hi = o.w_max > 0.0 ? o.w_max : 4.0 * top;
  const std::vector<double> grid = frequency_grid(g, 0.0, w_hi, o.samples_per_period);
  size_t k = 0;
  double lo = g.at(grid[0]).real();
  for (size_t i = 1; i < grid.size(); ++i) {
    const double r = g.at(grid[i]).real();
    if (r < lo) {
      lo = r;
      k = i;
    }
  }
  SimpleLimit out;
  out.min_real = lo;
  out.frequency = grid[k];
  if (!(lo < 0.0)) return out;
  // golden-section refinement between the neighbours of the smallest sample
  double a = grid[k > 0 ? k - 1 : 0], b = grid[std::min(k + 1, grid.size() - 1)];
  const double r = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - r * (b - a), d = a + r * (b - a);
  double fc = g.at(c).real(), fd = g.at(d).real();
  for (int i = 0; i < 200 && b - a > 1e-15 * b; ++i) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - r * (b - a);
      fc = g.at(c).real();
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + r * (b - a);
      fd = g.at(d).real();
    }
  }
  const double w = 0.5 * (a + b), v = g.at(w).real();
  if (v < out.min_real) {
    out.min_real = v;
    out.frequency = w;
  }
  out.gain = 1.0 / ((1.0 + mu) * -out.min_real);
  return out;
}

std::vector<LobePoint> stability_lobes(const TransferFunction& g, double mu, double n_min, double n_max, int count,
                                       const StabilityOptions& o) {
  if (!(n_min > 0.0 && n_max >= n_min && std::isfinite(n_max))) throw InputError("needs 0 < minimum <= maximum", "spindle speed range");
  if (count < 1 || count > 100000) throw InputError("must be from 1 to 100000", "lobe count");
  std::vector<LobePoint> out;
  for (int i = 0; i < count; ++i) {
    LobePoint p;
    p.spindle_speed = count == 1 ? n_min : n_min + (n_max - n_min) * i / (count - 1);
    p.limit = nyquist_limit(g, mu, 1.0 / p.spindle_speed, o);
    out.push_back(p);
  }
  return out;
}

}  // namespace polarcam::process

namespace polarcam::process {

SpeedRange default_lobe_range(const Cut& c) { return {0.5 / c.revolution_period, 2.0 / c.revolution_period}; }

}  // namespace polarcam::process
