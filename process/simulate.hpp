#pragma once
// Time-domain simulation of regenerative chatter (A. B. Dunckley (1978), Active Suppression of Machine Tool Chatter,
// Sec. 2.3 and the simulation program of App. B): the two masses of Eq. 2.2-2.3 driven by the cutting force
// F_c = K_c U(t), U(t) = U0 - X_w(t) + mu X_w(t - T) (Eq. 2.8), from rest with an untouched surface (X_w = 0 before
// t = 0), the cut of depth U0 starting at t = 0. Classical fourth-order Runge-Kutta with a step that divides T
// exactly; the delayed displacement between stored steps is the cubic Hermite interpolant of the stored
// displacement and velocity (fourth-order accurate, as the integrator).
#include <vector>

#include "process/structure.hpp"

namespace polarcam::process {

struct SimulationOptions {
  double duration = 0.0;        // s; 0: 40 revolutions
  // steps per revolution: 0 picks the smallest multiple of samples_per_revolution that keeps h w_top <= 0.05
  // (w_top the highest mode)
  int steps_per_revolution = 0;
  int samples_per_revolution = 400;  // rows kept for output (every k-th step)
};

struct SimulationSample {
  double t = 0.0, x_m = 0.0, x_w = 0.0, force = 0.0;  // s, m, m, N
  double x_t = 0.0;  // the tool's displacement by an active positioner (m; 0 without one)
};

struct SimulationResult {
  std::vector<SimulationSample> samples;
  double step = 0.0;               // integration step (s)
  double static_displacement = 0.0;  // X_w where the cut would settle (the equilibrium; m)
  // amplitude of X_w about the equilibrium: the largest |X_w - equilibrium| in each whole revolution
  std::vector<double> revolution_amplitude;
  // (amplitude of the last revolution / of the second)^(1/(revolutions - 2)): above 1 the vibration grows
  double growth_per_revolution = 0.0;
  // the vibration's frequency over the last quarter of the run: zero crossings of X_w about the equilibrium (rad/s)
  double frequency = 0.0;
  // half the range (max - min) of X_w in each whole revolution, and of the relative displacement X_w - X_t that
  // the cut sees (the same as X_w without a tool positioner), at the integration steps (m)
  std::vector<double> revolution_half_range, revolution_relative_half_range;
};

SimulationResult simulate_chatter(const TwoMassStructure& s, const Cut& c, double cutting_gain,
                                  const SimulationOptions& o = {});

// A tool displacement X_t imposed on the cut by an active tool positioner (Dunckley, Ch. 3 and Sec. 5.4): the depth
// of cut becomes U(t) = U0 - (X_w - X_t)(t) + mu (X_w - X_t)(t - T) (the program of App. B.5: U = U0 - D + mu D(t - T),
// D = X_w - X_t). The tool moves only at discrete instants (its moves) and samples the cut at others; X_t is
// constant between them. The integrator ends a sub-step at every such instant (and at every move delayed by T), so
// the piecewise constant X_t enters the Runge-Kutta stages exactly.
class ToolMotion {
 public:
  virtual ~ToolMotion() = default;
  // the first event (a move or a sampling instant) strictly after t; +infinity when none is due
  virtual double next_event(double t) const = 0;
  // the first move strictly after t; +infinity when none is due
  virtual double next_move(double t) const = 0;
  // X_t after every move at or before t (0 before the first); never called at a move's own instant
  virtual double position(double t) const = 0;
  // called at each instant next_event gave, in order, with the cutting force and X_w there; the tool may schedule
  // moves after t (never at or before t)
  virtual void event(double t, double force, double x_w) = 0;
};

// The simulation of simulate_chatter with a tool positioner in the loop. With `tool` null it is simulate_chatter,
// the same code.
SimulationResult simulate_chatter(const TwoMassStructure& s, const Cut& c, double cutting_gain,
                                  const SimulationOptions& o, ToolMotion* tool);

}  // namespace polarcam::process
