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
};

SimulationResult simulate_chatter(const TwoMassStructure& s, const Cut& c, double cutting_gain,
                                  const SimulationOptions& o = {});

}  // namespace polarcam::process
