#pragma once
// A cutting tool (an end mill) as the process models see it: a round cantilever of diameter d and overhang L
// from the holder, z teeth, a helix angle, and its material's breaking stress and Young's modulus. All SI.
// Optional parts feed the limits that need more than the tool (Fussell & Gagne, "Self-Directed Control of End
// Milling", 1991, Sec. 2-4; Elbestawi, "A Study of an Adaptive Control Constraint System for Milling", 1980,
// Sec. 6.2): docs/process.md.
#include <optional>

namespace polarcam::process {

// The tooth as Fussell & Gagne's Eq. 10-13 model it: a rectangular cantilever loaded at mid depth of cut.
struct ToothGeometry {
  double thickness_m = 0.0;  // a
  double width_m = 0.0;      // b
  double length_m = 0.0;     // l (the fluted length the load acts along)
};

// A cut, for the feed-per-tooth limit (Fussell & Gagne Eq. 14-18).
struct MillingCut {
  double spindle_speed_rad_s = 0.0;   // Omega
  double axial_depth_m = 0.0;         // d
  double radial_depth_m = 0.0;        // W
  double material_constant = 0.0;     // K of Eq. 16, hp/(in^3/min)^(3/4) as Fussell & Gagne tabulate it
};

// The structure's oriented transfer function at the tool, for Elbestawi's Eq. 6.2.
struct Structure {
  double re_g_min_m_per_N = 0.0;        // Re(G)_min, negative
  double cutting_stiffness_N_per_m2 = 0.0;  // r of Eq. 6.1: force per chip width per chip thickness
};

struct Tool {
  double diameter_m = 0.0;         // d (D)
  double length_m = 0.0;           // L: overhang from the holder
  int teeth = 0;                   // z (N_f)
  double helix_angle_rad = 0.0;
  double breaking_stress_Pa = 0.0; // sigma_S of Elbestawi's Eq. 5.33
  double youngs_modulus_Pa = 0.0;  // E
  // Fussell & Gagne's shank and tooth limits use the yield strength S_y and a factor of safety n; without
  // yield_strength they use the breaking stress.
  std::optional<double> yield_strength_Pa;
  double safety_factor = 1.0;
  std::optional<double> deflection_tolerance_m;  // y_tol of Eq. 21
  std::optional<ToothGeometry> tooth;
  std::optional<MillingCut> cut;
  std::optional<Structure> structure;
};

// Throws InputError naming the field (`tool.diameter`, ...) when a value cannot describe a tool: every length,
// stress and modulus positive and finite, teeth 1 to 100, the helix angle in [0, 90) deg, the factor of safety
// at least 1, the depth of cut no longer than the tooth, Re(G)_min negative.
void check_tool(const Tool& t);

}  // namespace polarcam::process
