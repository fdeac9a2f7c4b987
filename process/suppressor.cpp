#include "process/suppressor.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <string>

#include "cam/error.hpp"

namespace polarcam::process {
namespace {

constexpr long long kMaxSteps = 50'000'000;

std::complex<double> poly(const std::vector<double>& c, std::complex<double> s) {
  std::complex<double> v = 0.0;
  for (size_t i = c.size(); i-- > 0;) v = v * s + c[i];
  return v;
}

std::complex<double> poly_derivative(const std::vector<double>& c, std::complex<double> s) {
  std::complex<double> v = 0.0;
  for (size_t i = c.size(); i-- > 1;) v = v * s + static_cast<double>(i) * c[i];
  return v;
}

// The suppressor of Ch. 3 as a tool motion of the chatter integrator: samples at k T_s, steps spread over the
// period after each sample (Eq. 5.3).
class Suppressor final : public ToolMotion {
 public:
  Suppressor(const SuppressorSpec& spec, const SuppressorModel& m, SuppressionRun& run, double end)
      : Ts_(spec.sample_period), S_(spec.step_size), end_(end), m_(m), run_(run) {
    per_period_ = static_cast<long long>(std::floor(spec.max_step_rate * spec.sample_period * (1.0 + 1e-12)));
    run_.steps_per_period_limit = per_period_;
  }

  double next_event(double t) const override { return std::min(sample_time(), next_move(t)); }
  double next_move(double t) const override {
    auto it = std::upper_bound(times_.begin(), times_.end(), t);
    return it == times_.end() ? std::numeric_limits<double>::infinity() : *it;
  }
  double position(double t) const override {
    const auto i = std::upper_bound(times_.begin(), times_.end(), t) - times_.begin();
    return i == 0 ? 0.0 : static_cast<double>(run_.steps[static_cast<size_t>(i - 1)].position) * S_;
  }
  void event(double t, double force, double) override {
    if (t != sample_time()) return;  // a step: position() follows the list
    if (t >= end_) {  // the run's end: no period follows
      ++index_;
      return;
    }
    // Eq. 3.2 one sample ahead: the displacement at k + 1 from the forces up to k
    const double xp = m_.A1 * force + m_.A2 * f1_ - m_.B1 * p1_ - m_.B2 * p2_;
    f1_ = force;
    p2_ = p1_;
    p1_ = xp;
    const double target = xp / S_;
    if (!(std::abs(target) < 9e15))
      throw InputError("the model's prediction is beyond 9e15 steps of the positioner: the model or the cut diverges "
                       "(check the [suppressor] model, or give a shorter --duration)",
                       "--suppress");
    const long long want = std::llround(target) - q_;
    long long n = want;
    if (std::llabs(n) > per_period_) {
      n = n > 0 ? per_period_ : -per_period_;
      ++run_.saturated_periods;
      if (!run_.first_saturation) run_.first_saturation = t;
      run_.max_shortfall = std::max(run_.max_shortfall, std::llabs(want) - per_period_);
    }
    ++run_.periods;
    const long long count = std::llabs(n);
    if (static_cast<long long>(run_.steps.size()) + count > kMaxSteps)
      throw InputError("the suppressor would issue more than 5e7 steps: give a larger step size or a shorter --duration",
                       "--suppress");
    const int dir = n > 0 ? 1 : -1;
    const double k = static_cast<double>(index_);
    for (long long j = 0; j < count; ++j) {
      q_ += dir;
      // Eq. 5.3: SPEED counts, a step, SPEED counts: step j at (j + 1/2) / N of the period
      const double ts =
          Ts_ * (k + static_cast<double>(2 * j + 1) / static_cast<double>(2 * count));
      run_.steps.push_back({ts, dir, q_});
      times_.push_back(ts);
      (dir > 0 ? run_.steps_forward : run_.steps_reverse) += 1;
    }
    run_.max_steps_in_period = std::max(run_.max_steps_in_period, count);
    ++index_;
  }

 private:
  double sample_time() const { return static_cast<double>(index_) * Ts_; }
  double Ts_, S_, end_;
  SuppressorModel m_;
  SuppressionRun& run_;
  long long per_period_ = 0, q_ = 0, index_ = 0;
  double f1_ = 0.0, p1_ = 0.0, p2_ = 0.0;  // F_c(k-1), X_p(k), X_p(k-1)
  std::vector<double> times_;
};

void check_stable(const SuppressorModel& m, const std::string& key) {
  // both roots of z^2 + B1 z + B2 inside the unit circle (Jury): |B2| < 1, 1 + B1 + B2 > 0, 1 - B1 + B2 > 0
  if (!(std::abs(m.B2) < 1.0 && 1.0 + m.B1 + m.B2 > 0.0 && 1.0 - m.B1 + m.B2 > 0.0))
    throw InputError("the suppressor's model is not stable at this sample period (a pole of z^2 + B1 z + B2 on or "
                     "outside the unit circle): check the model's keys",
                     key);
}

}  // namespace

const char* to_string(ModelSource s) {
  switch (s) {
    case ModelSource::structure: return "structure";
    case ModelSource::given: return "given";
    case ModelSource::discrete: return "discrete";
  }
  return "?";
}

SuppressorModel zoh_second_order(double wn, double zeta, double K, double Ts) {
  const double sigma = zeta * wn, wd = wn * std::sqrt(1.0 - zeta * zeta);
  const double a = std::exp(-sigma * Ts), c = std::cos(wd * Ts), s = std::sin(wd * Ts);
  SuppressorModel m;
  m.B1 = -2.0 * a * c;
  m.B2 = a * a;
  m.A1 = K * (1.0 - a * (c + sigma / wd * s));
  m.A2 = K * (a * a + a * (sigma / wd * s - c));
  m.omega_n = wn;
  m.zeta = zeta;
  m.gain = K;
  return m;
}

SuppressorModel structure_model(const TwoMassStructure& st, double Ts) {
  const TransferFunction g = workpiece_compliance(st);
  double best = -1.0, wn = 0.0, zeta = 0.0, K = 0.0;
  for (const std::complex<double>& p : poles(g)) {
    if (!(p.imag() > 0.0)) continue;
    const std::complex<double> r = poly(g.num, p) / poly_derivative(g.den, p);
    const double sigma = -p.real(), size = std::abs(r) / sigma;
    if (size > best) {
      best = size;
      wn = std::abs(p);
      zeta = sigma / wn;
      K = (std::complex<double>(0.0, 2.0 * p.imag()) * r).real() / (wn * wn);
    }
  }
  if (!(best > 0.0)) throw InputError("the structure has no mode of vibration to model", "suppressor.model");
  return zoh_second_order(wn, zeta, K, Ts);
}

void check(const SuppressorSpec& s) {
  auto positive = [](double v, const char* key, const char* what) {
    if (!(std::isfinite(v) && v > 0.0)) throw InputError(std::string("must be ") + what, std::string("suppressor.") + key);
  };
  positive(s.sample_period, "sample_period", "a positive sample period (s)");
  positive(s.step_size, "step_size", "a positive step size (m)");
  positive(s.max_step_rate, "max_step_rate", "a positive step rate (steps/s)");
  if (!(s.max_step_rate * s.sample_period * (1.0 + 1e-12) >= 1.0))
    throw InputError("allows no step in a sample period: give at least 1 / sample_period steps/s",
                     "suppressor.max_step_rate");
  if (s.max_step_rate * s.sample_period > 1e6)
    throw InputError("allows more than 1e6 steps in a sample period", "suppressor.max_step_rate");
  positive(s.model_frequency_scale, "model_frequency_scale", "a positive factor");
  if (s.source == ModelSource::given) {
    positive(s.omega_n, "omega_n", "the model's natural frequency (rad/s), positive");
    if (!(s.zeta > 0.0 && s.zeta < 1.0)) throw InputError("must be a damping ratio between 0 and 1", "suppressor.zeta");
    if (!(std::isfinite(s.gain) && s.gain != 0.0)) throw InputError("must be a nonzero static gain (m/N)", "suppressor.gain");
  }
  if (s.source == ModelSource::discrete) {
    for (auto [v, k] : {std::pair{s.A1, "A1"}, {s.A2, "A2"}, {s.B1, "B1"}, {s.B2, "B2"}})
      if (!std::isfinite(v)) throw InputError("must be a finite number", std::string("suppressor.") + k);
    if (s.model_frequency_scale != 1.0)
      throw InputError("applies to the structure and given models only", "suppressor.model_frequency_scale");
  }
}

SuppressorModel suppressor_model(const TwoMassStructure& st, const SuppressorSpec& spec) {
  check(spec);
  SuppressorModel m;
  switch (spec.source) {
    case ModelSource::structure: {
      const SuppressorModel b = structure_model(st, spec.sample_period);
      m = zoh_second_order(b.omega_n * spec.model_frequency_scale, b.zeta, b.gain, spec.sample_period);
      break;
    }
    case ModelSource::given:
      m = zoh_second_order(spec.omega_n * spec.model_frequency_scale, spec.zeta, spec.gain, spec.sample_period);
      break;
    case ModelSource::discrete:
      m.A1 = spec.A1;
      m.A2 = spec.A2;
      m.B1 = spec.B1;
      m.B2 = spec.B2;
      break;
  }
  check_stable(m, "suppressor.model");
  if (spec.source == ModelSource::discrete) {
    // what the coefficients stand for (Eq. 4.8-4.9 and the static gain), as identification reads them; w_n and
    // zeta stay 0 when the poles are not a damped oscillation
    m.gain = (m.A1 + m.A2) / (1.0 + m.B1 + m.B2);
    try {
      const SecondOrder so = to_second_order(m, spec.sample_period);
      m.omega_n = so.omega_n;
      m.zeta = so.zeta;
    } catch (const InputError&) {
    }
  }
  if (!std::isfinite(m.A1 + m.A2 + m.B1 + m.B2))
    throw InputError("the suppressor's model is not finite at this sample period", "suppressor.model");
  return m;
}

SuppressionRun simulate_suppression(const TwoMassStructure& s, const Cut& c, double kc, const SuppressorSpec& spec,
                                    const SimulationOptions& o) {
  SuppressionRun run;
  run.model = suppressor_model(s, spec);
  run.without = simulate_chatter(s, c, kc, o);
  const double end = run.without.samples.back().t;
  Suppressor tool(spec, run.model, run, end);
  run.with = simulate_chatter(s, c, kc, o, &tool);
  // the steps the last period would take after the end were never taken
  while (!run.steps.empty() && run.steps.back().t > end) {
    (run.steps.back().dir > 0 ? run.steps_forward : run.steps_reverse) -= 1;
    run.steps.pop_back();
  }
  run.final_position = run.steps.empty() ? 0 : run.steps.back().position;
  run.max_step_rate_used = static_cast<double>(run.max_steps_in_period) / spec.sample_period;
  return run;
}

}  // namespace polarcam::process
