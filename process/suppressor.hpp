#pragma once
// The stepper-driven chatter suppressor of A. B. Dunckley (1978), Active Suppression of Machine Tool Chatter, Ch. 3
// and Sec. 5.4, simulated in the regenerative chatter loop (process/simulate.hpp):
//
// - every sample period T_s the cutting force F_c is sampled (Sec. 5.2.4) and the second-order discrete model of
//   the machine-workpiece structure (Eq. 3.1-3.2) predicts the workpiece displacement one sample ahead:
//     X_p(k+1) = A1 F_c(k) + A2 F_c(k-1) - B1 X_p(k) - B2 X_p(k-1)
//   (a parallel model: its own past outputs, never a measured displacement, as in the program of App. B.5);
// - the controller rounds the prediction to the nearest whole step of the positioner, q(k+1) = round(X_p(k+1) / S),
//   and issues the N = q(k+1) - q(k) steps "from its present position to the predicted position" (Sec. 3.1);
// - the N steps are spread evenly over the next sample period: Eq. 5.3 (SPEED = TIMER / (2 N)) waits SPEED counts,
//   steps, waits SPEED counts again, so step j (0-based) of period k is at t = (k + (j + 1/2) / N) T_s;
// - the actuator is a stepping motor with zero inertia and no damping (Sec. 3.1): the tool is displaced by exactly
//   S at each step, X_t = S q; it moves at most floor(R T_s) steps in a period (R, its largest step rate: Sec. 5.4.1
//   "care must be taken ... to prevent the step pulse rate exceeding the motor maximum speed"). A period that
//   would need more issues that many, and the run reports it as saturated (when and how often);
// - the tool follows the workpiece, so the cut sees D = X_w - X_t: U = U0 - D(t) + mu D(t - T) (App. B.5).
//
// The positioner's own dynamics (the second-order lag of App. B.5 and Sec. 3.3, K_t, M_t, C_t) are not modelled.
#include <optional>
#include <string>
#include <vector>

#include "process/identify.hpp"
#include "process/simulate.hpp"
#include "process/structure.hpp"

namespace polarcam::process {

// Where the suppressor's model comes from.
enum class ModelSource {
  structure,  // the structure's dominant mode (the largest loop of its polar plot, Sec. 3.3's 'best' model)
  given,      // omega_n, zeta and static gain given (e.g. from `polarcam identify`), held between samples
  discrete,   // the coefficients A1, A2, B1, B2 of Eq. 3.2 given at the sample period
};
const char* to_string(ModelSource s);

// The [suppressor] table of the chatter structure file.
struct SuppressorSpec {
  double sample_period = 0.0;   // T_s (s)
  double step_size = 0.0;       // S, the tool's displacement per step (m)
  double max_step_rate = 0.0;   // R, the stepper's largest step rate (steps/s)
  ModelSource source = ModelSource::structure;
  double omega_n = 0.0, zeta = 0.0, gain = 0.0;  // given: rad/s, ratio, m/N
  double A1 = 0.0, A2 = 0.0, B1 = 0.0, B2 = 0.0;   // discrete: m/N, m/N, -, -
  double model_frequency_scale = 1.0;            // the model's omega_n times this (Sec. 3.3: 0.95 and 1.05)
};

// The discrete model of Eq. 3.1 with what it stands for.
// Eq. 3.2's coefficients (the identified model's form, process/identify.hpp) and what they stand for.
struct SuppressorModel : DiscreteModel {
  double omega_n = 0.0, zeta = 0.0, gain = 0.0;  // rad/s, ratio, static gain (A1 + A2) / (1 + B1 + B2) (m/N)
};

// G(s) = K w_n^2 / (s^2 + 2 zeta w_n s + w_n^2) sampled with its input held between samples (a zero-order hold, as
// the sample-and-hold of Sec. 5.2.4 holds the force):
//   B1 = -2 a cos(w_d T_s), B2 = a^2, a = e^{-zeta w_n T_s}
//   A1 = K (1 - a (cos + (sigma / w_d) sin)), A2 = K (a^2 + a ((sigma / w_d) sin - cos)),   arguments w_d T_s.
SuppressorModel zoh_second_order(double omega_n, double zeta, double gain, double sample_period);
// The second-order model of the structure's dominant mode: the mode whose polar loop is the largest (the largest
// |residue| / decay rate), with omega_n and zeta of its poles and the gain that gives the model the same residue
// there (K = Re[2 j w_d r] / w_n^2), held between samples.
SuppressorModel structure_model(const TwoMassStructure& s, double sample_period);
// The model the spec asks for (its frequency scaled by model_frequency_scale), checked stable (both poles inside
// the unit circle): InputError naming the key otherwise.
SuppressorModel suppressor_model(const TwoMassStructure& s, const SuppressorSpec& spec);

// Checks the spec: positive finite sample period, step size and step rate, at least one step per period, a model
// of the source's keys. InputError naming "suppressor.<key>".
void check(const SuppressorSpec& spec);

struct PositionerStep {
  double t = 0.0;         // s
  int dir = 1;            // +1 or -1
  long long position = 0;  // the positioner's position after the step (steps)
};

struct SuppressionRun {
  SuppressorModel model;
  SimulationResult without;  // the cut without the suppressor (simulate_chatter)
  SimulationResult with;     // the same cut with it; samples carry x_t
  std::vector<PositionerStep> steps;  // every step issued, in time order
  long long steps_forward = 0, steps_reverse = 0;
  long long final_position = 0;       // steps
  long long max_steps_in_period = 0;
  long long steps_per_period_limit = 0;  // floor(R T_s): the most steps the stepper can take in a period
  double max_step_rate_used = 0.0;    // the largest N / T_s of a period (steps/s)
  long long periods = 0, saturated_periods = 0;
  std::optional<double> first_saturation;  // the start of the first saturated period (s)
  long long max_shortfall = 0;  // the most steps a saturated period left for later
};

// The cut at cutting gain K_c simulated without and with the suppressor. InputError naming "--suppress" when the
// run would issue more than 5e7 steps or the prediction leaves the range of whole steps.
SuppressionRun simulate_suppression(const TwoMassStructure& s, const Cut& c, double cutting_gain,
                                    const SuppressorSpec& spec, const SimulationOptions& o = {});

}  // namespace polarcam::process
