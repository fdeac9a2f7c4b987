#pragma once
// Stepping-motor pull-out torque: the largest load torque a motor carries without losing steps at a given step
// rate. Two models:
//  - electrical (Eq. 5.17 = F.6 of A. Fahim's thesis (1983)): from the supply voltage, the torque and voltage
//    constants, the rotor teeth and the winding's resistance and inductance,
//      T_p(w) = c_p V K_T / sqrt(R^2 + w^2 L^2) - K_V w R K_T / (N_s (R^2 + w^2 L^2)),
//    w the electrical angular frequency (N_s times the shaft's rad/s). c_p is the amplitude of the fundamental of
//    one phase's voltage per unit supply voltage, computed from the switching sequence of Table F.1: 1.17632 for
//    the wave (half-step) scheme the thesis uses, 4/pi for full step with two windings on, 2 sqrt(2)/pi with one.
//  - curve: a datasheet's pull-out curve (torque against step rate), interpolated monotonically (PCHIP); a rate
//    outside the tabulated range is an error, never an extrapolation.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "cam/error.hpp"

namespace polarcam {

// The three energisation schemes of Table F.1.
enum class Energisation { wave, full_one, full_two };
const char* to_string(Energisation e);
// "wave" (or "half_step"), "full_one", "full_two"; nullopt for anything else.
std::optional<Energisation> parse_energisation(const std::string& s);

// One switching state per step of Table F.1: for each step, which of SW1..SW4 are on.
struct SwitchingSequence {
  std::vector<std::array<bool, 4>> steps;
};
const SwitchingSequence& table_f1(Energisation e);

// Fundamental of phase A's voltage (SW1 on: +V, SW2 on: -V) per unit supply voltage, as amplitude and phase (rad),
// over one cycle of the sequence (the Fourier coefficient of Eq. F.1's n = 0 term); phase B likewise (SW3, SW4).
struct Fundamental {
  double amplitude, phase;
};
Fundamental phase_fundamental(const SwitchingSequence& seq, int phase /*0 = A, 1 = B*/);
// c_p of the pull-out formula for a scheme: the amplitude of its phase fundamental.
double pullout_coefficient(Energisation e);
// Motor steps per rotor-tooth pitch (one electrical cycle): 8 for wave, 4 for the full-step schemes.
int steps_per_cycle(Energisation e);

struct ElectricalMotor {
  double supply_voltage = 0.0;  // V, V
  double K_T = 0.0;             // N m/A, torque constant
  double K_V = 0.0;             // V s/rad, voltage (back-emf) constant per winding, per shaft rad/s
  int rotor_teeth = 0;          // N_s
  double R_a = 0.0;             // ohm, winding and drive circuit
  double L_a = 0.0;             // H, winding
  Energisation energisation = Energisation::wave;

  void validate() const;                 // throws InputError
  double steps_per_rev() const;          // N_s * steps_per_cycle
  double pullout(double omega_e) const;  // N m at electrical angular frequency omega_e (rad/s), Eq. 5.17 generalised
  double pullout_at_rate(double step_rate_hz) const;  // omega_e = 2 pi N_s step_rate / steps_per_rev
};

// A rate outside a tabulated pull-out curve.
class OutsideCurveError : public InputError {
 public:
  using InputError::InputError;
};

class PulloutCurve {
 public:
  // Points of (step rate in Hz, torque in N m), rates strictly increasing from zero or more, torques positive;
  // at least two. Throws InputError naming the offending row (1-based).
  PulloutCurve(std::vector<double> rate_hz, std::vector<double> torque_Nm);
  // Monotone piecewise-cubic (PCHIP; linear with fewer than four points). Throws OutsideCurveError outside
  // [first rate, last rate].
  double at(double rate_hz) const;
  const std::vector<double>& rates() const { return rate_; }
  const std::vector<double>& torques() const { return torque_; }

 private:
  struct Impl;
  std::vector<double> rate_, torque_;
  std::shared_ptr<const Impl> impl_;
};

struct StepperMotor {
  std::variant<ElectricalMotor, PulloutCurve> model;
  double steps_per_rev = 0.0;           // motor steps per shaft revolution as driven (step rates are in these)
  std::optional<double> max_step_rate;  // Hz: the drive's limit, when known

  bool electrical() const { return std::holds_alternative<ElectricalMotor>(model); }
  // Pull-out torque at a step rate (steps per second, >= 0). Throws OutsideCurveError for a curve's range.
  double pullout_at_rate(double step_rate_hz) const;
  // Short description for reports, e.g. "wave (half step), 24 V, K_T 0.0759 N m/A, ..., 400 steps/rev".
  std::string describe() const;
};

StepperMotor make_electrical_motor(const ElectricalMotor& m, std::optional<double> max_step_rate = std::nullopt);
StepperMotor make_curve_motor(PulloutCurve curve, double steps_per_rev,
                              std::optional<double> max_step_rate = std::nullopt);

}  // namespace polarcam
