#pragma once
// Identification of a second-order structure from a measured response (A. B. Dunckley (1978), Active Suppression of
// Machine Tool Chatter, Ch. 4): the logarithmic decrement of a free vibration (Sec. 4.2, Eq. 4.1-4.2 corrected,
// docs/chatter.md) and the second-order discrete model (Eq. 4.3)
//   c_k = A1 m_{k-1} + A2 m_{k-2} - B1 c_{k-1} - B2 c_{k-2}      (m: force, c: displacement)
// by batch least squares (Eq. 4.4-4.7) and by recursive least squares with forgetting, converted to w_n, zeta
// (Eq. 4.8-4.9) and the static gain K = (A1 + A2) / (1 + B1 + B2) (m/N; see docs/chatter.md on Eq. 4.10).
#include <optional>
#include <string>
#include <vector>

namespace polarcam::process {

// A response sampled every `period` seconds; force empty when the record has none.
struct Response {
  double period = 0.0;
  std::vector<double> displacement, force;
};
// A CSV file with a header naming t_s and displacement_m, and force_N when the force was recorded (any order, other
// columns ignored); t_s evenly spaced. InputError naming FILE:LINE otherwise.
Response read_response_csv(const std::string& path);
Response parse_response_csv(const std::string& text, const std::string& name);

struct Decrement {
  double delta = 0.0;      // ln(M1 / M2) per period, fitted over every peak used
  double zeta = 0.0;       // delta / sqrt(4 pi^2 + delta^2)
  double omega_d = 0.0;    // 2 pi / period between peaks (rad/s)
  double omega_n = 0.0;    // omega_d / sqrt(1 - zeta^2) (Eq. 4.2)
  int peaks = 0;
};
// The positive peaks of a free vibration about zero (one per cycle, between upward zero crossings, refined by a
// parabola) down to `floor` times the first; nullopt with fewer than three.
std::optional<Decrement> log_decrement(const std::vector<double>& x, double period, double floor = 0.05);

struct DiscreteModel {
  double A1 = 0.0, A2 = 0.0, B1 = 0.0, B2 = 0.0;
};
// Batch least squares over every sample from k = 2 (the normal equations of Eq. 4.7, solved by a QR factorisation
// of the scaled regressors).
DiscreteModel batch_least_squares(const std::vector<double>& force, const std::vector<double>& displacement);

struct RlsOptions {
  double forgetting = 1.0;            // lambda in (0, 1]: 1 weighs every sample alike
  double initial_covariance = 1e6;    // P0 = this times the identity (on the scaled regressors)
};
DiscreteModel recursive_least_squares(const std::vector<double>& force, const std::vector<double>& displacement,
                                      const RlsOptions& o = {});

struct SecondOrder {
  double omega_n = 0.0, zeta = 0.0;  // rad/s, ratio
  double gain = 0.0;                 // static displacement per force (m/N)
};
// Eq. 4.8-4.9 and the static gain; InputError when the model is not an underdamped, stable second-order system.
SecondOrder to_second_order(const DiscreteModel& m, double period);

}  // namespace polarcam::process
