#pragma once
// Stability of regenerative chatter (A. B. Dunckley (1978), Active Suppression of Machine Tool Chatter, Sec. 2.2.4):
// the limiting cutting gain K_c and the chatter frequency of 1 + K_c H(s) G(s) = 0 (process/structure.hpp).
//
// Nyquist (Sec. 2.2.4.2-2.2.4.3): the open loop K_c H(j w) G(j w) passes through -1 where H G is real and negative,
// at K_c = -1 / (H G); the smallest such K_c is the gain at which a root of the characteristic equation first
// reaches the imaginary axis (all roots lie in the left half-plane at K_c = 0, the structure being damped), and its
// w the chatter frequency. Simple criterion (Sec. 2.2.4.1, Eq. 2.20): on the imaginary axis K_c G = -1/H, whose real
// part is at most -1/(1 + mu) (-0.5 at mu = 1, the document's case), so Re[K_c G] > -1/(1 + mu) at every w
// guarantees stability whatever the revolution period: K_c < 1 / ((1 + mu) |min Re G|).
#include <optional>
#include <vector>

#include "process/structure.hpp"

namespace polarcam::process {

// How finely the frequency axis is searched (the problem is G, mu and T).
struct StabilityOptions {
  // Highest frequency searched (rad/s); 0: four times the structure's highest mode, extended while a crossing
  // beyond could still give a smaller gain (|H| <= 1 + mu bounds it).
  double w_max = 0.0;
  // Samples per period 2 pi / T of H(j w) (each period holds two crossings of the real axis); the grid is also
  // refined around every mode down to a hundredth of its half-power bandwidth.
  int samples_per_period = 48;
};

struct NyquistLimit {
  std::optional<double> critical_gain;   // K_c (N/m); none when H G never crosses the negative real axis
  double chatter_frequency = 0.0;        // w at that crossing (rad/s)
  int crossings = 0;                     // crossings of the negative real axis found up to w_max
};

// The limiting K_c by the Nyquist criterion for the cut's overlap and revolution period.
NyquistLimit nyquist_limit(const TransferFunction& g, double overlap, double period, const StabilityOptions& o = {});

struct SimpleLimit {
  std::optional<double> gain;  // 1 / ((1 + mu) |min Re G|); none when Re G >= 0 everywhere
  double min_real = 0.0;       // min over w of Re G(j w) (m/N)
  double frequency = 0.0;      // where (rad/s)
};
SimpleLimit simple_criterion(const TransferFunction& g, double overlap, const StabilityOptions& o = {});

// Stability lobes: the Nyquist limit at spindle speeds n = 1/T (rev/s) from n_min to n_max, `count` evenly spaced.
struct LobePoint {
  double spindle_speed = 0.0;  // rev/s
  NyquistLimit limit;
};
std::vector<LobePoint> stability_lobes(const TransferFunction& g, double overlap, double n_min, double n_max,
                                       int count, const StabilityOptions& o = {});

}  // namespace polarcam::process

namespace polarcam::process {

// The spindle speeds a lobe table covers when none are asked: half to twice the cut's speed 1/T (rev/s).
struct SpeedRange {
  double n_min = 0.0, n_max = 0.0;  // rev/s
};
SpeedRange default_lobe_range(const Cut& c);

}  // namespace polarcam::process
