#pragma once
// The adaptive-control (A/C) constraint loop of M. A. Elbestawi, "A Study of an Adaptive Control Constraint
// System for Milling" (PhD thesis, McMaster University, 1980), Ch. 4-5, simulated at the rate of the NC
// interpolator's interrupt (5 kHz, App. III):
//   - the NC feed servo, Eq. 5.20: V(s)/X(s) = 6398.424 s / ((s + 427.414)(s + 14.970)), taken as a position loop
//     v' = -(p1 + p2) v - p1 p2 x + K x_com (K = 6398.424, p1 = 427.414, p2 = 14.970), discretised exactly for a
//     command held over each interrupt (zero-order hold); the commanded position x_com advances in whole basic
//     length units from a feed accumulator, as the DDA of App. III does;
//   - the control law, Eq. 4.18 / 5.19: e_f = (F_nom - F) / F_nom, V_com = integral of (K_ac e_f + B de_f/dt),
//     evaluated once per control period on the sampled force;
//   - the cutting force with the cut delay, Eq. 4.17: F = K_C h, the chip h = x(t) - x(t - tau) the table travel
//     over the last tooth period (tau = 2 pi / (z Omega)), zero before the tool reaches the workpiece's wall; at
//     a steady speed it is the lumped model F = C v(t - tau) with C = K_C tau (Eq. 4.2-4.4);
//   - the cutter's flexibility (spindle stiffness K_S), Eq. 5.13-5.16: the tool deflects by F / K_S, so each
//     pass cuts h / (1 + mu), mu = K_C / K_S; for small tau this is Eq. 5.21's F(s)/V(s) = K_S / (s + K_S/K'_C)
//     with K'_C = K_C tau;
//   - the impact strategies for entering the cut: A (Sec. 5.4, Eq. 5.17-5.19) and B (Sec. 5.8).
// SI units throughout: m, s, N; K_ac in m/s^2, B in m/s (docs/process.md: the thesis prints B in mm/s^2).
#include <complex>
#include <optional>
#include <string>
#include <vector>

namespace polarcam::process {

// Eq. 5.20: the closed-loop NC servo from commanded position to table speed.
struct FeedServo {
  double gain = 6398.424;  // 1/s^2: the numerator of Eq. 5.20
  double pole1 = 427.414;  // 1/s
  double pole2 = 14.970;   // 1/s
};

enum class ImpactStrategy {
  none,  // the law of Eq. 5.19 from the first sample, starting at the rapid feed
  A,     // Sec. 5.4: below the threshold the rapid feed (Eq. 5.17); above it, the slow feed for a time (Eq. 5.18),
         // then Eq. 5.19 from the slow feed
  B,     // Sec. 5.8: above the threshold, the drive's speed command and the NC pulses held at zero for hold_time,
         // then Eq. 5.19 from zero with the NC loop gain divided by 3 for reduced_gain_time
};

struct AcLoopSettings {
  FeedServo servo;
  double dda_rate_hz = 5000.0;        // the interrupt rate of App. III
  double blu_m = 2.54e-6;             // the basic length unit, 0.0001 in
  double control_period_s = 2e-4;     // how often the force is sampled and Eq. 5.19 evaluated (a whole number of
                                      // interrupts)
  double K_ac = 25.4e-3;              // m/s^2
  double B = 1.0e-3;                  // m/s
  double F_nom = 1320.0;              // N
  double rapid_feed = 12.5e-3;        // m/s: V_max of Eq. 5.17 (750 mm/min); also the most Eq. 5.19 may command
  ImpactStrategy strategy = ImpactStrategy::A;
  double impact_threshold = 45.0;     // N
  double slow_feed = 7.5e-3 / 60.0;   // m/s: Eq. 5.18 (7.5 mm/min)
  double slow_time = 0.100;           // s: strategy A
  double hold_time = 0.040;           // s: strategy B
  double reduced_gain_time = 0.100;   // s: strategy B, after the hold
  // the cut
  int teeth = 4;
  double spindle_speed_rad_s = 600.0 * 2.0 * 3.14159265358979323846 / 60.0;
  double cutting_stiffness = 8.97e6;          // K_C, N/m (Eq. 4.17's k a b)
  std::optional<double> spindle_stiffness;    // K_S, N/m; absent: a rigid spindle
  double entry_distance = 5e-3;               // m from the start to the workpiece's wall
  double duration_s = 1.0;
};

struct AcSample {
  double t = 0.0;        // s
  double feed = 0.0;     // m/s, the table's speed
  double force = 0.0;    // N
  double command = 0.0;  // m/s, V_com
};

struct AcResult {
  std::vector<AcSample> series;     // one sample per interrupt, from t = 0
  std::optional<double> impact_time_s;  // when the sampled force first exceeded the threshold
  double peak_force = 0.0;          // N
  double peak_force_time_s = 0.0;
  double final_feed = 0.0;          // m/s: the mean over the last tenth of the run
  double final_force = 0.0;         // N: likewise
  int command_limited_samples = 0;  // control samples at which Eq. 5.19 asked for less than 0 or more than the
                                    // rapid feed and was held at that bound
  double tooth_period_s = 0.0;
};

// Throws InputError naming the setting (`control.K_ac`, ...) when it cannot describe a loop.
void check(const AcLoopSettings& s);
AcResult simulate_ac_loop(const AcLoopSettings& s);

// The steady feed the law settles at: F_nom / (K_C tau) (the integral action drives e_f to zero).
double ac_steady_feed(const AcLoopSettings& s);

// Eq. 5.21: the open loop 6398.424 B K_S (s + K_ac/B) / (F_nom s (s + K_S/K'_C)(s + p2)(s + p1)), with the pole
// at K_S/K'_C the printed (s + K_S) stands for. Its closed-loop poles for the loop gain at the given K_ac: the
// roots of s (s + K_S/K'_C)(s + p1)(s + p2) + k (s + K_ac/B), k = gain B K_S / F_nom, sorted by real part
// (slowest first) then imaginary part. Units as above (K_S N/m, K'_C N s/m).
struct Eq521 {
  FeedServo servo;
  double K_ac = 25.4e-3, B = 1.0e-3, F_nom = 1320.0;
  double K_S = 7.03e6;            // N/m
  double K_C_rate = 224.25e3;     // K'_C, N s/m
};
std::vector<std::complex<double>> closed_loop_poles(const Eq521& e);
// Eq. 5.21 for a simulated loop: its servo, gains and F_nom, K_S its spindle stiffness, K'_C = K_C tau; nullopt
// for a rigid spindle (Eq. 5.21 needs K_S).
std::optional<Eq521> eq521_of(const AcLoopSettings& s);
// The damping ratio -Re/|p| of the dominant (slowest) complex pair; nullopt when all the poles are real.
std::optional<double> dominant_damping(const std::vector<std::complex<double>>& poles);

// Exact zero-order-hold discretisation of x' = A x + B u over dt: x[k+1] = Ad x[k] + Bd u[k]. Row-major n x n A,
// n x m B; the results in the same layout.
struct Discrete {
  int n = 0, m = 0;
  std::vector<double> Ad, Bd;
};
Discrete discretise_zoh(const std::vector<double>& A, const std::vector<double>& B, int n, int m, double dt);

const char* strategy_name(ImpactStrategy s);

}  // namespace polarcam::process
