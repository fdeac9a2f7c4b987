// Process monitoring from one sampled signal: see monitor.hpp and docs/monitoring.md.
#include "process/monitor.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <unsupported/Eigen/FFT>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "process/checks.hpp"
#include "process/force_estimator.hpp"

namespace polarcam::process {
namespace {

// Appends an exceedance to `events`, merged into the last event of its kind when that one's last exceedance
// ended no more than `gap` seconds before this one starts.
void add_event(std::vector<MonitorEvent>& events, EventKind kind, double start, double end, double value,
               double threshold, double gap, double frequency = 0.0) {
  for (auto it = events.rbegin(); it != events.rend(); ++it) {
    if (it->kind != kind) continue;
    if (start - it->end_s <= gap + 1e-9 * std::max(1.0, end)) {
      it->end_s = end;
      ++it->count;
      return;
    }
    break;
  }
  MonitorEvent e;
  e.kind = kind;
  e.time_s = end;
  e.end_s = end;
  e.value = value;
  e.threshold = threshold;
  e.frequency_hz = frequency;
  events.push_back(e);
}

}  // namespace

MonitorSignal select_signal(const SignalRecord& r, const std::string& file, const std::string& column,
                            bool estimate, double friction) {
  MonitorSignal s;
  s.start_s = r.start_s;
  s.sample_rate_hz = 1.0 / r.period_s;
  auto quantity = [](const std::string& name) {
    auto ends = [&](const char* suffix) {
      const std::string u(suffix);
      return name.size() >= u.size() && name.compare(name.size() - u.size(), u.size(), u) == 0;
    };
    return ends("_N") ? "force" : ends("_A") ? "current" : "";
  };
  if (estimate) {
    if (!column.empty()) throw InputError("--signal and --estimate-force exclude each other", "--estimate-force");
    const auto* I = r.find("current_A");
    const auto* W = r.find("speed_rad_per_s");
    if (!I || !W)
      throw InputError("--estimate-force needs the columns current_A and speed_rad_per_s (the feed motor's current "
                       "and speed)",
                       file);
    if (!(std::isfinite(friction) && friction > 0.0))
      throw InputError("must be a positive friction, e.g. \"0.196 N m s/rad\"", "--friction");
    FeedDrive d = peng1989_drive();
    d.B = friction;
    d.T = r.period_s;
    s.name = "estimated_force_N";
    s.quantity = "force";
    s.x = estimate_force(d, *I, *W);
    return s;
  }
  std::string name = column;
  if (name.empty()) name = r.find("force_N") ? "force_N" : r.find("current_A") ? "current_A" : r.names.front();
  const auto* x = r.find(name);
  if (!x) {
    std::string have;
    for (const auto& n : r.names) have += (have.empty() ? "" : ", ") + n;
    throw InputError("the file has no column " + name + " (it has " + have + ")", "--signal");
  }
  s.name = name;
  s.quantity = quantity(name);
  s.x = *x;
  return s;
}

const char* to_string(EventKind k) {
  switch (k) {
    case EventKind::breakage: return "breakage";
    case EventKind::chatter: return "chatter";
    case EventKind::overload: return "overload";
  }
  return "?";
}

std::vector<ToothPeriod> tooth_period_averages(const std::vector<double>& x, double fs, double rev_per_s,
                                               int teeth) {
  if (!positive(fs)) throw InputError("must be a positive sample rate", "sample rate");
  if (!positive(rev_per_s)) throw InputError("must be a positive speed, e.g. \"600 rpm\"", "--spindle");
  if (teeth < 1 || teeth > 1000) throw InputError("must be a whole number from 1 to 1000", "--teeth");
  const double P = fs / (rev_per_s * teeth);  // samples per tooth period
  if (!(P >= 2.0))
    throw InputError("a tooth period is " + std::to_string(P) +
                         " samples: the signal must be sampled at least twice per tooth period",
                     "--spindle");
  const double N = static_cast<double>(x.size());
  const size_t periods = static_cast<size_t>(std::floor(N / P * (1.0 + 1e-12)));
  std::vector<ToothPeriod> out;
  out.reserve(periods);
  for (size_t i = 0; i < periods; ++i) {
    const double a = static_cast<double>(i) * P, b = std::min(N, static_cast<double>(i + 1) * P);
    const size_t k0 = static_cast<size_t>(std::floor(a));
    double sum = 0.0;
    for (size_t k = k0; k < x.size() && static_cast<double>(k) < b; ++k) {
      const double lo = std::max(a, static_cast<double>(k)), hi = std::min(b, static_cast<double>(k + 1));
      if (hi > lo) sum += x[k] * (hi - lo);
    }
    out.push_back({a / fs, b / fs, sum / (b - a)});
  }
  return out;
}

Differences tooth_differences(const std::vector<ToothPeriod>& p, double floor) {
  Differences d;
  for (size_t t = 1; t < p.size(); ++t) {
    const double d1 = p[t].mean - p[t - 1].mean;
    d.d2.push_back(d.d1.empty() ? 0.0 : d1 - d.d1.back());
    d.d1.push_back(d1);
    const double den = std::max(std::abs(p[t - 1].mean), floor);
    d.normalised.push_back(den > 0.0 ? d1 / den : 0.0);
  }
  return d;
}

std::vector<double> welch_psd(const std::vector<double>& x, double fs, size_t segment) {
  if (segment < 8 || (segment & (segment - 1)) != 0 || segment > x.size())
    throw InputError("the PSD segment must be a power of two of at least 8 samples within the record", "welch_psd");
  std::vector<double> w(segment);
  double w2 = 0.0;
  for (size_t i = 0; i < segment; ++i) {  // periodic Hann
    w[i] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(segment));
    w2 += w[i] * w[i];
  }
  double mean = 0.0;
  for (double v : x) mean += v;
  mean /= static_cast<double>(x.size());
  Eigen::FFT<double> fft;
  std::vector<double> psd(segment / 2 + 1, 0.0), in(segment);
  std::vector<std::complex<double>> out;
  size_t count = 0;
  for (size_t start = 0; start + segment <= x.size(); start += segment / 2, ++count) {
    for (size_t i = 0; i < segment; ++i) in[i] = (x[start + i] - mean) * w[i];
    fft.fwd(out, in);
    for (size_t k = 0; k < psd.size(); ++k) psd[k] += std::norm(out[k]);
  }
  for (size_t k = 0; k < psd.size(); ++k) {
    const double one_sided = (k == 0 || k == segment / 2) ? 1.0 : 2.0;
    psd[k] *= one_sided / (fs * w2 * static_cast<double>(count));
  }
  return psd;
}

MonitorResult monitor_signal(const std::vector<double>& x, const MonitorOptions& o) {
  if (!positive(o.learn_revolutions) || o.learn_revolutions > 1e6)
    throw InputError("must be a positive number of revolutions", "--learn-revolutions");
  if (!positive(o.threshold_factor)) throw InputError("must be a positive number", "--threshold-factor");
  if (!(std::isfinite(o.min_threshold) && o.min_threshold >= 0.0))
    throw InputError("must be a number >= 0", "--min-threshold");
  if (o.threshold && !positive(*o.threshold)) throw InputError("must be a positive number", "--threshold");
  if (o.chatter_setpoint && !positive(*o.chatter_setpoint))
    throw InputError("must be a positive amplitude", "--chatter-setpoint");
  if (o.overload && !std::isfinite(*o.overload)) throw InputError("must be a finite number", "--overload");
  if (!positive(o.amplitude_factor)) throw InputError("must be a positive number", "--amplitude-factor");
  for (double v : x)
    if (!std::isfinite(v)) throw InputError("the signal has a value that is not finite", "signal");

  const auto periods = tooth_period_averages(x, o.sample_rate_hz, o.spindle_rev_per_s, o.teeth);
  MonitorResult r;
  r.tooth_frequency_hz = o.spindle_rev_per_s * o.teeth;
  r.samples_per_tooth = o.sample_rate_hz / r.tooth_frequency_hz;
  r.tooth_periods = periods.size();
  const double rev = 1.0 / o.spindle_rev_per_s;
  r.learn_end_s = o.learn_revolutions * rev;
  const double record_s = static_cast<double>(x.size()) / o.sample_rate_hz;
  if (r.learn_end_s + rev > record_s * (1.0 + 1e-12))
    throw InputError("the record (" + significant(record_s, 6) + " s) must hold the " +
                         significant(o.learn_revolutions, 6) + " learning revolutions and one more",
                     "--learn-revolutions");

  // breakage: learn the run-out from the first revolutions
  size_t learn = 0;
  double learn_mean = 0.0;
  while (learn < periods.size() && periods[learn].end_s <= r.learn_end_s * (1.0 + 1e-12))
    learn_mean += periods[learn++].mean;
  if (learn < 2) throw InputError("the learning revolutions hold fewer than two tooth periods", "--learn-revolutions");
  learn_mean /= static_cast<double>(learn);
  const Differences d = tooth_differences(periods, 0.1 * std::abs(learn_mean));
  for (size_t t = 1; t < learn; ++t)
    r.learned_max_normalised = std::max(r.learned_max_normalised, std::abs(d.normalised[t - 1]));
  r.breakage_threshold =
      o.threshold ? *o.threshold : std::max(o.threshold_factor * r.learned_max_normalised, o.min_threshold);
  for (size_t t = std::max<size_t>(learn, 1); t < periods.size(); ++t) {
    const double v = std::abs(d.normalised[t - 1]);
    bool hit = v > r.breakage_threshold;
    if (o.rule == BreakageRule::fussell) hit = hit && std::abs(d.d2[t - 1]) > std::abs(d.d1[t - 1]);
    if (hit)
      add_event(r.events, EventKind::breakage, periods[t].start_s, periods[t].end_s, d.normalised[t - 1],
                r.breakage_threshold, rev);
  }
  if (o.overload)
    for (const auto& p : periods)
      if (p.mean > *o.overload) add_event(r.events, EventKind::overload, p.start_s, p.end_s, p.mean, *o.overload, rev);

  // chatter: Welch PSD over consecutive blocks
  if (o.chatter) {
    if (!positive(o.segment_spindle_periods) || o.segment_spindle_periods > 1e4)
      throw InputError("must be a positive number", "--segment-revolutions");
    size_t seg = 8;
    while (static_cast<double>(seg) < o.segment_spindle_periods * o.sample_rate_hz * rev) seg *= 2;
    const size_t block = seg * 5 / 2;
    r.chatter_block_s = static_cast<double>(block) / o.sample_rate_hz;
    r.chatter_blocks = x.size() / block;
    const size_t first = o.chatter_setpoint ? 0 : 1;
    if (r.chatter_blocks > first) {
      const double df = o.sample_rate_hz / static_cast<double>(seg);
      auto amplitude = [&](size_t b) {
        double m = 0.0, s = 0.0;
        for (size_t i = b * block; i < (b + 1) * block; ++i) m += x[i];
        m /= static_cast<double>(block);
        for (size_t i = b * block; i < (b + 1) * block; ++i) s += (x[i] - m) * (x[i] - m);
        return std::sqrt(2.0 * s / static_cast<double>(block));
      };
      r.chatter_setpoint = o.chatter_setpoint ? *o.chatter_setpoint : o.amplitude_factor * amplitude(0);
      // the bins near a spindle harmonic (DC and the tooth frequency's harmonics among them)
      std::vector<bool> harmonic(seg / 2 + 1, false);
      for (size_t k = 0; k < harmonic.size(); ++k) {
        const double f = static_cast<double>(k) * df, m = std::round(f * rev);
        harmonic[k] = std::abs(f - m / rev) <= o.harmonic_bins * df;
      }
      const double ft = r.tooth_frequency_hz;
      for (size_t b = first; b < r.chatter_blocks; ++b) {
        const double FR = amplitude(b);
        if (!(FR > r.chatter_setpoint)) continue;  // Eq. 22
        const std::vector<double> chunk(x.begin() + static_cast<std::ptrdiff_t>(b * block),
                                        x.begin() + static_cast<std::ptrdiff_t>((b + 1) * block));
        const auto psd = welch_psd(chunk, o.sample_rate_hz, seg);
        double phi_t = 0.0, phi_p = 0.0;
        size_t kp = 0;
        for (size_t k = 0; k < psd.size(); ++k) {
          const double f = static_cast<double>(k) * df;
          if (std::abs(f - ft) <= o.harmonic_bins * df) phi_t = std::max(phi_t, psd[k]);
          if (!harmonic[k] && psd[k] > phi_p) {
            phi_p = psd[k];
            kp = k;
          }
        }
        if (!(phi_p > phi_t)) continue;  // Eq. 23-24
        double fp = static_cast<double>(kp) * df;
        if (kp > 0 && kp + 1 < psd.size()) {  // parabola through the peak and its neighbours
          const double a = psd[kp - 1], c = psd[kp + 1], den = a - 2.0 * phi_p + c;
          if (den < 0.0) fp += 0.5 * (a - c) / den * df;
        }
        const double start = static_cast<double>(b * block) / o.sample_rate_hz;
        add_event(r.events, EventKind::chatter, start, start + r.chatter_block_s, FR, r.chatter_setpoint, 0.0, fp);
      }
    }
  }
  std::stable_sort(r.events.begin(), r.events.end(),
                   [](const MonitorEvent& a, const MonitorEvent& b) { return a.time_s < b.time_s; });
  return r;
}

}  // namespace polarcam::process
