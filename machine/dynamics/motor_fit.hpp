#pragma once
// Fitting the electrical pull-out model (Eq. 5.17 = F.6, generalised in stepper.hpp) to a measured pull-out curve,
// as Appendix F.3 of A. Fahim's thesis (1983) compares the model with measurements. The supply voltage, winding
// resistance, rotor teeth and energisation are known (nameplate, ohmmeter); the fit finds the torque constant K_T,
// the voltage constant K_V and the inductance L_a (the three combinations the curve determines: the low-speed
// torque c_p V K_T / R_a, the time constant L_a / R_a and the back-emf term K_V K_T / (N_s R_a)).
// The start comes from a scan over L_a with K_T and K_T K_V solved by linear least squares (the model is linear in
// them for a fixed L_a); Ceres then minimises a robust loss (Cauchy by default) of the torque residuals, so a few
// bad readings do not drag the curve. Everything is in SI: step rates in Hz (motor steps per second as driven),
// torques in N m.
#include <optional>
#include <string>
#include <vector>

#include "machine/dynamics/stepper.hpp"

namespace polarcam {

struct PulloutPoint {
  double rate_hz = 0.0;
  double torque = 0.0;
};

enum class RobustLoss { none, huber, cauchy };
std::optional<RobustLoss> parse_robust_loss(const std::string& s);
const char* to_string(RobustLoss l);

struct MotorFitOptions {
  RobustLoss loss = RobustLoss::cauchy;
  std::optional<double> loss_scale;  // N m; default 2.5 x the robust (MAD) spread of the starting fit's residuals
  double outlier_sigmas = 3.0;       // points whose residual exceeds this many loss scales are flagged
};

struct MotorFitResult {
  ElectricalMotor motor;                         // the known constants with the fitted K_T, K_V, L_a
  std::optional<double> K_T_sd, K_V_sd, L_a_sd;  // approximate standard errors (from the inliers' Jacobian)
  std::vector<double> residuals;                 // N m, model minus measurement, per point
  std::vector<bool> outlier;
  double rms = 0.0;               // N m, over the inliers
  double max_abs_residual = 0.0;  // N m, over the inliers
  double loss_scale = 0.0;        // N m
  RobustLoss loss = RobustLoss::cauchy;
  double initial_cost = 0.0, final_cost = 0.0;
  int iterations = 0;
  bool converged = false;
  std::string report;  // Ceres' brief report
};

// `known` supplies supply_voltage, R_a, rotor_teeth and energisation (its K_T, K_V, L_a are ignored). At least
// four points with at least three distinct rates. Throws InputError for unusable input.
MotorFitResult fit_electrical_motor(const std::vector<PulloutPoint>& points, const ElectricalMotor& known,
                                    const MotorFitOptions& opt = {});

}  // namespace polarcam
