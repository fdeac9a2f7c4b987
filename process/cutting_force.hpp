#pragma once
// The lumped cutting-force model of M. A. Elbestawi, "A Study of an Adaptive Control Constraint System for
// Milling" (PhD thesis, McMaster University, 1980), Sec. 4.4: the force follows the feed speed one tooth period
// late, F(t) = C v(t - tau) (Eq. 4.2, 4.3), with C = K b a (Eq. 4.4) proportional to the axial depth b and the
// radial depth a. Sec. 4.5's simulation writes the same model as F = k a b (x(t) - x(t - tau)) (Eq. 4.17), the
// chip of the table travel over the last tooth period; at a steady speed v that is C v with K = k tau.
// SI throughout: K in N s/m^3 (N/mm^2 per mm/s is 1e9 N s/m^3), C in N s/m, k in N/m^3.
#include <functional>
#include <vector>

namespace polarcam::process {

// The tooth period tau = 2 pi / (z Omega) (s): z teeth at the spindle speed Omega (rad/s).
double tooth_period(int teeth, double spindle_speed_rad_s);

struct LumpedForceModel {
  double K = 0.0;    // N s/m^3 (Eq. 4.4)
  double tau = 0.0;  // s, the tooth period

  // C = K b a (N s/m), Eq. 4.4.
  double C(double axial_depth_b, double radial_depth_a) const { return K * axial_depth_b * radial_depth_a; }
  // F(t) = C v(t - tau), Eq. 4.2, for a feed speed history v(t) (m/s).
  double force(double axial_depth_b, double radial_depth_a, const std::function<double(double)>& v, double t) const;
};

// K from one measured or estimated cut (Sec. 4.4): the force F at the feed per tooth f_t, depths b and a, tooth
// period tau: v = f_t / tau, C = F / v, K = C / (b a). InputError naming the quantity when one is not positive.
LumpedForceModel calibrate_lumped_model(double F, double feed_per_tooth, double axial_depth_b,
                                        double radial_depth_a, double tau);

// K from Eq. 4.17's specific force k (N/m^3): K = k tau.
LumpedForceModel lumped_model_from_specific_force(double k, double tau);

// The steady force at feed speed v for each axial depth (case A of Sec. 4.5: the rapid phase at b = 2.5 mm and
// the force the moment the depth steps to 10 mm, the chip still that of the rapid speed).
std::vector<double> lumped_forces(const LumpedForceModel& m, const std::vector<double>& axial_depths,
                                  double radial_depth_a, double v);

}  // namespace polarcam::process
