// A synthetic milling force (docs/monitoring.md): see milling_signal.hpp.
#include "process/milling_signal.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "cam/error.hpp"
#include "process/checks.hpp"

namespace polarcam::process {
namespace {

bool non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

// Standard normal deviates by Box-Muller from the generator's raw 64-bit words (not std::normal_distribution,
// whose algorithm each standard library chooses).
class Normal {
 public:
  explicit Normal(uint64_t seed) : rng_(seed) {}
  double operator()() {
    if (have_) {
      have_ = false;
      return spare_;
    }
    const double u1 = (static_cast<double>(rng_() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
    const double u2 = static_cast<double>(rng_() >> 11) * 0x1.0p-53;          // [0, 1)
    const double rho = std::sqrt(-2.0 * std::log(u1)), a = 2.0 * std::numbers::pi * u2;
    spare_ = rho * std::sin(a);
    have_ = true;
    return rho * std::cos(a);
  }

 private:
  std::mt19937_64 rng_;
  double spare_ = 0.0;
  bool have_ = false;
};

}  // namespace

double milling_pass_start(const MillingSignalOptions& o, long k) {
  return static_cast<double>(k) / (o.teeth * o.spindle_rev_per_s);
}

SignalRecord milling_force_signal(const MillingSignalOptions& o) {
  if (!positive(o.duration_s) || o.duration_s > 3600.0) throw InputError("must be in (0, 3600] s", "--duration");
  if (!positive(o.sample_rate_hz) || o.sample_rate_hz > 1e6) throw InputError("must be in (0, 1 MHz]", "--rate");
  if (o.duration_s * o.sample_rate_hz > 2e7) throw InputError("more than 20 million samples", "--duration");
  if (!positive(o.spindle_rev_per_s)) throw InputError("must be a positive speed, e.g. \"600 rpm\"", "--spindle");
  if (o.teeth < 1 || o.teeth > 100) throw InputError("must be a whole number from 1 to 100", "--teeth");
  if (!(positive(o.engagement) && o.engagement <= 1.0)) throw InputError("must be in (0, 1]", "--engagement");
  if (!non_negative(o.peak_force_N)) throw InputError("must be a force >= 0", "--peak-force");
  if (!(non_negative(o.runout) && o.runout < 0.5)) throw InputError("must be in [0, 0.5)", "--runout");
  if (!non_negative(o.noise_N)) throw InputError("must be a force >= 0", "--noise");
  if (o.break_at_s && !non_negative(*o.break_at_s)) throw InputError("must be a time >= 0", "--break-at");
  if (o.broken_tooth < 0 || o.broken_tooth >= o.teeth)
    throw InputError("must be a tooth from 0 to teeth - 1", "--broken-tooth");
  if (o.chatter_at_s) {
    if (!non_negative(*o.chatter_at_s)) throw InputError("must be a time >= 0", "--chatter-at");
    if (!(positive(o.chatter_frequency_hz) && o.chatter_frequency_hz < 0.5 * o.sample_rate_hz))
      throw InputError("must be a positive frequency below half the sample rate", "--chatter-frequency");
    if (!non_negative(o.chatter_force_N)) throw InputError("must be a force >= 0", "--chatter-force");
  }
  const int Z = o.teeth;
  const double rev = 1.0 / o.spindle_rev_per_s, pass = rev / Z, cut = o.engagement * rev;
  // the chip of every pass that starts within the record (and those still cutting at its start: none, t >= 0)
  const long passes = static_cast<long>(std::ceil(o.duration_s / pass)) + 1;
  std::vector<double> chip(static_cast<size_t>(passes));
  double surface = 0.0;  // the deepest cut so far, in feeds per tooth, relative to the nominal path at pass 0
  for (long k = 0; k < passes; ++k) {
    const int j = static_cast<int>(k % Z);
    const bool broken = o.break_at_s && j == o.broken_tooth && milling_pass_start(o, k) >= *o.break_at_s;
    // a broken tooth reaches nothing; the others reach k + r_j feeds
    const double reach =
        broken ? -1e300 : static_cast<double>(k) + o.runout * std::cos(2.0 * std::numbers::pi * j / Z);
    const double h = k == 0 ? 1.0 : std::max(0.0, reach - surface);  // the first pass cuts one feed
    chip[static_cast<size_t>(k)] = h;
    surface = k == 0 ? reach : std::max(surface, reach);
  }
  SignalRecord r;
  r.start_s = 0.0;
  r.period_s = 1.0 / o.sample_rate_hz;
  r.names = {"force_N"};
  const size_t n = static_cast<size_t>(std::llround(o.duration_s * o.sample_rate_hz));
  std::vector<double> F(std::max<size_t>(n, 2));
  Normal noise(o.seed);
  for (size_t i = 0; i < F.size(); ++i) {
    const double t = static_cast<double>(i) * r.period_s;
    double f = 0.0;
    // the passes in cut at t: those that started within the last `cut` seconds
    const long last = static_cast<long>(std::floor(t / pass + 1e-12));
    for (long k = last; k >= 0 && t - milling_pass_start(o, k) < cut; --k) {
      const double phi = std::numbers::pi * (t - milling_pass_start(o, k)) / cut;  // 0 .. pi over the cut
      f += o.peak_force_N * chip[static_cast<size_t>(k)] * std::sin(phi);
    }
    if (o.chatter_at_s && t >= *o.chatter_at_s)
      f += o.chatter_force_N * std::min(1.0, (t - *o.chatter_at_s) / 0.1) *
           std::sin(2.0 * std::numbers::pi * o.chatter_frequency_hz * (t - *o.chatter_at_s));
    F[i] = f + o.noise_N * noise();
  }
  r.columns = {std::move(F)};
  return r;
}

}  // namespace polarcam::process
