#pragma once
// A cutting tool's limits, each from the equation that defines it (docs/process.md gives the sources and every
// correction to the printed equations):
//   M. A. Elbestawi, "A Study of an Adaptive Control Constraint System for Milling", PhD thesis, McMaster
//   University, 1980: Sec. 5.10 (Eq. 5.32-5.35, Table 5.1), Sec. 6.2 (Eq. 6.2);
//   B. K. Fussell, D. P. Gagne, "Self-Directed Control of End Milling", WL-TR-91-4027, 1991: Eq. 7, 9-13,
//   14-19, 20-21 and Table 1.
// Every function takes and returns SI units.
#include <optional>

#include "process/tool.hpp"

namespace polarcam::process {

// Second moment of area of a round shank, pi d^4 / 64 (m^4).
double shank_second_moment(double d);
// Elbestawi Eq. 5.33 with the /(32 L) the print drops: the tip force whose bending stress at the holder is sigma_S.
double breakage_force(double d, double L, double sigma_S);
// The cantilever's tip stiffness 3 E I / L^3 (Fussell & Gagne Eq. 20; their Table 1's 90 200 N/cm).
double cantilever_stiffness(double d, double L, double E);
// Elbestawi Eq. 5.34 as printed, pi d^4 E / (1.5 * 64 L^3) = E I / (1.5 L^3): the stiffness his rapid feed
// (Eq. 5.35, Table 5.1) is computed with. It is the cantilever's 3 E I / L^3 divided by 4.5.
double elbestawi_tool_stiffness(double d, double L, double E);
// Elbestawi Eq. 5.32-5.35: the rapid feed per tooth at which the first force peak on entry (Eq. 5.32:
// F_C = f_t K_t / 0.3) reaches the breakage force: f_tr = 0.3 F_max / K_t = 0.9 (sigma_S/E) L^2/d.
double rapid_feed_per_tooth(double d, double L, double sigma_S, double E);
// Fussell & Gagne Eq. 7: the total tip force at which the shank's maximum shear stress reaches S_y / (2 n).
double shank_force_limit(double D, double L, double S_y, double n);
// Fussell & Gagne Eq. 21 with the L^3 the print drops: the perpendicular force that deflects the tip by y_tol,
// y_tol 3 E I / L^3.
double deflection_force_limit(double D, double L, double E, double y_tol);
// Fussell & Gagne Eq. 13: the tooth force at which the tooth's maximum shear stress reaches S_y / (2 n); the
// load at mid depth of cut d (Eq. 9's (l - d)).
double tooth_force_limit(const ToothGeometry& g, double axial_depth, double S_y, double n);
// Fussell & Gagne Eq. 14-18: the feed per tooth at which the power the tooth force F_tooth delivers at the
// tooth speed (Eq. 14, 15 with the circumference pi D) equals the power of material removal K Q^(3/4)
// (Eq. 16, 17). Computed in the document's units (lbf, ft/min, in^3/min, hp); returns metres.
double feed_per_tooth_limit(double F_tooth, double D, int teeth, const MillingCut& cut);
// The constant of Eq. 18, (c / (6 * 12 * 33000))^(4/3) in the document's units: c = 1 with the circumference
// pi D (3.15e-9), c = 2 with Eq. 15's printed 2 pi D (7.95e-9, the value printed in Eq. 18).
double fussell_eq18_constant(double circumference_factor);
// Elbestawi Eq. 6.2: the limit width of chip b_lim = -1 / (2 r Re(G)_min).
double chatter_limit_width(double r, double re_g_min);

struct ToolLimits {
  double second_moment_m4 = 0.0;
  double breakage_force_N = 0.0;            // Eq. 5.33
  double stiffness_N_per_m = 0.0;           // 3 E I / L^3
  double elbestawi_stiffness_N_per_m = 0.0; // Eq. 5.34 as printed
  double rapid_feed_per_tooth_m = 0.0;      // Eq. 5.35
  double shank_force_limit_N = 0.0;         // Eq. 7 (S_y: yield strength, else breaking stress)
  std::optional<double> deflection_force_limit_N;   // Eq. 21, with a deflection tolerance
  std::optional<double> tooth_force_limit_N;        // Eq. 13, with [tooth] and [cut]
  std::optional<double> feed_per_tooth_limit_m;     // Eq. 18, with [tooth] and [cut]
  std::optional<double> chatter_limit_width_m;      // Eq. 6.2, with [structure]
};

// All the limits the tool's data allow; check_tool first (InputError naming the field), and InputError (place
// "tool") when the numbers give a limit that is zero or not finite.
ToolLimits tool_limits(const Tool& t);

}  // namespace polarcam::process
