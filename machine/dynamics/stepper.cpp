#include "machine/dynamics/stepper.hpp"

#include "cam/format.hpp"

// Boost 1.74's pchip.hpp calls isnan unqualified: <math.h> puts it in the global namespace first.
#include <math.h>

#include <array>
#include <boost/math/interpolators/pchip.hpp>
#include <cmath>
#include <complex>
#include <numbers>
#include <sstream>

namespace polarcam {
namespace {

constexpr double kPi = std::numbers::pi;

std::string num(double v, int prec = 6) { return significant(v, prec); }

}  // namespace

const char* to_string(Energisation e) {
  static constexpr const char* kNames[] = {"wave", "full_one", "full_two"};  // in the order of the enum
  return kNames[static_cast<int>(e)];
}

std::optional<Energisation> parse_energisation(const std::string& s) {
  if (s == "wave" || s == "half_step") return Energisation::wave;
  if (s == "full_one") return Energisation::full_one;
  if (s == "full_two") return Energisation::full_two;
  return std::nullopt;
}

const SwitchingSequence& table_f1(Energisation e) {
  // Table F.1, transcribed row by row: the switches SW1..SW4 that are ON at each step.
  constexpr bool I = true, O = false;
  static const SwitchingSequence one{{{O, O, O, I}, {I, O, O, O}, {O, O, I, O}, {O, I, O, O}}};
  static const SwitchingSequence two{{{I, O, O, I}, {I, O, I, O}, {O, I, I, O}, {O, I, O, I}}};
  static const SwitchingSequence half{
      {{O, O, O, I}, {I, O, O, I}, {I, O, O, O}, {I, O, I, O}, {O, O, I, O}, {O, I, I, O}, {O, I, O, O}, {O, I, O, I}}};
  switch (e) {
    case Energisation::full_one:
      return one;
    case Energisation::full_two:
      return two;
    case Energisation::wave:
      break;
  }
  return half;
}

Fundamental phase_fundamental(const SwitchingSequence& seq, int phase) {
  // v(t) is piecewise constant over M equal slots; its first Fourier coefficient is exact:
  // c1 = (2/T) int v e^{-j w t} dt = (1 - e^{-j 2 pi/M}) / (j pi) * sum_k v_k e^{-j 2 pi k/M}
  const int M = static_cast<int>(seq.steps.size());
  std::complex<double> sum = 0.0;
  for (int k = 0; k < M; ++k) {
    const auto& sw = seq.steps[static_cast<size_t>(k)];
    const double v =
        (sw[static_cast<size_t>(2 * phase)] ? 1.0 : 0.0) - (sw[static_cast<size_t>(2 * phase + 1)] ? 1.0 : 0.0);
    sum += v * std::polar(1.0, -2.0 * kPi * k / M);
  }
  const std::complex<double> c1 = (1.0 - std::polar(1.0, -2.0 * kPi / M)) / std::complex<double>(0.0, kPi) * sum;
  return {std::abs(c1), std::arg(c1)};
}

double pullout_coefficient(Energisation e) {
  static const std::array<double, 3> c{phase_fundamental(table_f1(Energisation::wave), 0).amplitude,
                                       phase_fundamental(table_f1(Energisation::full_one), 0).amplitude,
                                       phase_fundamental(table_f1(Energisation::full_two), 0).amplitude};
  return c[static_cast<size_t>(e)];
}

int steps_per_cycle(Energisation e) { return static_cast<int>(table_f1(e).steps.size()); }

void ElectricalMotor::validate() const {
  auto pos = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError(std::string(what) + " must be positive");
  };
  pos(supply_voltage, "the supply voltage");
  pos(K_T, "the torque constant K_T");
  if (!(K_V >= 0.0) || !std::isfinite(K_V)) throw InputError("the voltage constant K_V must be zero or positive");
  if (rotor_teeth <= 0) throw InputError("the number of rotor teeth N_s must be a positive whole number");
  pos(R_a, "the winding resistance R_a");
  if (!(L_a >= 0.0) || !std::isfinite(L_a)) throw InputError("the winding inductance L_a must be zero or positive");
}

double ElectricalMotor::steps_per_rev() const {
  return static_cast<double>(rotor_teeth) * steps_per_cycle(energisation);
}

double ElectricalMotor::pullout(double omega_e) const {
  const double w = std::abs(omega_e);
  const double z2 = R_a * R_a + w * w * L_a * L_a;
  return pullout_coefficient(energisation) * supply_voltage * K_T / std::sqrt(z2) -
         K_V * w * R_a * K_T / (static_cast<double>(rotor_teeth) * z2);
}

double ElectricalMotor::pullout_at_rate(double step_rate_hz) const {
  return pullout(2.0 * kPi * static_cast<double>(rotor_teeth) * step_rate_hz / steps_per_rev());
}

struct PulloutCurve::Impl {
  std::optional<boost::math::interpolators::pchip<std::vector<double>>> pchip;
};

PulloutCurve::PulloutCurve(std::vector<double> rate_hz, std::vector<double> torque_Nm)
    : rate_(std::move(rate_hz)), torque_(std::move(torque_Nm)) {
  if (rate_.size() != torque_.size()) throw InputError("the pull-out curve needs a torque for every rate");
  if (rate_.size() < 2) throw InputError("the pull-out curve needs at least two points");
  for (size_t i = 0; i < rate_.size(); ++i) {
    const std::string row = "pull-out curve point " + std::to_string(i + 1) + ": ";
    if (!(rate_[i] >= 0.0) || !std::isfinite(rate_[i]))
      throw InputError(row + "the step rate must be zero or positive");
    if (i > 0 && !(rate_[i] > rate_[i - 1])) throw InputError(row + "step rates must increase");
    if (!(torque_[i] > 0.0) || !std::isfinite(torque_[i])) throw InputError(row + "the torque must be positive");
  }
  auto impl = std::make_shared<Impl>();
  if (rate_.size() >= 4) {
    std::vector<double> x = rate_, y = torque_;
    impl->pchip.emplace(std::move(x), std::move(y));
  }
  impl_ = std::move(impl);
}

double PulloutCurve::at(double rate_hz) const {
  const double f = std::abs(rate_hz);
  if (!(f >= rate_.front() && f <= rate_.back()))
    throw OutsideCurveError("step rate " + num(f) + " Hz is outside the pull-out curve (" + num(rate_.front()) +
                            " .. " + num(rate_.back()) + " Hz)");
  if (impl_->pchip) return (*impl_->pchip)(f);
  size_t i = 1;
  while (i + 1 < rate_.size() && rate_[i] < f) ++i;
  const double w = (f - rate_[i - 1]) / (rate_[i] - rate_[i - 1]);
  return torque_[i - 1] + w * (torque_[i] - torque_[i - 1]);
}

double StepperMotor::pullout_at_rate(double step_rate_hz) const {
  if (const auto* e = std::get_if<ElectricalMotor>(&model)) return e->pullout_at_rate(step_rate_hz);
  return std::get<PulloutCurve>(model).at(step_rate_hz);
}

std::string StepperMotor::describe() const {
  std::ostringstream os;
  if (const auto* e = std::get_if<ElectricalMotor>(&model)) {
    os << "electrical, " << to_string(e->energisation) << ", " << num(e->supply_voltage) << " V, K_T " << num(e->K_T)
       << " N m/A, K_V " << num(e->K_V) << " V s/rad, N_s " << e->rotor_teeth << ", R_a " << num(e->R_a) << " ohm, L_a "
       << num(e->L_a) << " H";
  } else {
    const auto& c = std::get<PulloutCurve>(model);
    os << "pull-out curve of " << c.rates().size() << " points, " << num(c.rates().front()) << " .. "
       << num(c.rates().back()) << " Hz";
  }
  os << ", " << num(steps_per_rev) << " steps/rev";
  if (max_step_rate) os << ", max " << num(*max_step_rate) << " Hz";
  return os.str();
}

StepperMotor make_electrical_motor(const ElectricalMotor& m, std::optional<double> max_step_rate) {
  m.validate();
  if (max_step_rate && !(*max_step_rate > 0.0)) throw InputError("the maximum step rate must be positive");
  return StepperMotor{m, m.steps_per_rev(), max_step_rate};
}

StepperMotor make_curve_motor(PulloutCurve curve, double steps_per_rev, std::optional<double> max_step_rate) {
  if (!(steps_per_rev > 0.0) || !std::isfinite(steps_per_rev))
    throw InputError("steps per revolution must be positive");
  if (max_step_rate && !(*max_step_rate > 0.0)) throw InputError("the maximum step rate must be positive");
  return StepperMotor{std::move(curve), steps_per_rev, max_step_rate};
}

}  // namespace polarcam
