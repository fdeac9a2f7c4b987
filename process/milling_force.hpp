#pragma once
// The helical end mill as M. A. Elbestawi's tooth-slice model (A Study of an Adaptive Control Constraint System
// for Milling, 1980, Sec. 5.2, Eq. 5.1-5.8) computes its force: the axial depth b is cut into slices of height
// db; the slice at height z lags the tip by the helix, z tan(lambda) / r (Eq. 5.1); a tooth's slice at rotation
// angle phi cuts a chip of thickness h = f_t sin(phi) (Eq. 5.3-5.6 for a feed per tooth f_t small against the
// radius) while phi lies between the entry and exit angles of the engagement, and carries the force K db h
// (Eq. 5.7); the cutter's force is the sum over slices and teeth (Eq. 5.8). Elbestawi uses one constant K for
// the force he computes; here each slice has a tangential force K_t db h, a radial force K_r db h and an axial
// force K_a db h (specific cutting forces in N/m^2), projected on the feed frame (docs/process.md).
//
// Angles (the convention of most milling texts): the cutter turns clockwise seen from the spindle (M03), the feed
// is +x, the angle phi of a tooth is measured clockwise from +y. Up (conventional) milling with the material on the
// +y side engages phi in [0, psi]; down (climb) milling with the material on the -y side engages
// phi in [pi - psi, pi], psi the engaged angle. Forces are those on the tool, in N.
#include <vector>

namespace polarcam::process {

struct SliceCutter {
  int teeth = 0;
  double radius_m = 0.0;      // r = d / 2
  double helix_rad = 0.0;     // lambda, in [0, 90) deg
  double axial_depth_m = 0.0; // b
  double K_t = 0.0;           // N/m^2: tangential force per chip area
  double K_r = 0.0;           // N/m^2: radial force per chip area (towards the cutter's axis on the tool: positive)
  double K_a = 0.0;           // N/m^2: axial force per chip area (optional, 0)
};

// Throws InputError naming the field when the cutter cannot be modelled.
void check_slice_cutter(const SliceCutter& c);

enum class MillingMode { up, down };
const char* to_string(MillingMode m);

// The angles (rad) between which a tooth cuts: entry <= phi <= exit, within [0, pi].
struct Immersion {
  double entry = 0.0;
  double exit = 0.0;
  double angle() const { return exit - entry; }
};
// The engagement of a straight cut of radial width a with a cutter of radius r: psi = acos(1 - a / r) (pi for
// a >= 2 r), placed for the mode.
double straight_engaged_angle(double radial_width, double radius);
Immersion immersion_for(MillingMode mode, double engaged_angle);

// A force on the tool in the feed frame: x along the feed, y the Altintas y (+y the up-milling material side),
// z along the cutter's axis.
struct CutterForce {
  double x = 0.0, y = 0.0, z = 0.0;
};

// The number of slices the model cuts the depth into: enough that neighbouring slices lag by at most
// `max_lag_rad` (one slice for a straight-fluted cutter).
int slice_count(const SliceCutter& c, double max_lag_rad = 0.5 * 3.14159265358979323846 / 180.0);

// Eq. 5.1-5.8: the force at the cutter's rotation angle theta (rad; tooth 0's tip at phi = theta) for a feed per
// tooth f_t (m). `tooth` >= 0: that tooth's force only.
CutterForce slice_force(const SliceCutter& c, const Immersion& im, double feed_per_tooth, double theta,
                        int slices, int tooth = -1);

// The force averaged over a revolution, in closed form: each slice's average is the straight-fluted cutter's,
// N b f_t / (8 pi) [K_t cos 2phi - K_r (2 phi - sin 2 phi)] (x), [K_t (2 phi - sin 2phi) + K_r cos 2 phi] (y),
// N b f_t K_a / (2 pi) [-cos phi] (z), between entry and exit.
CutterForce mean_force(const SliceCutter& c, const Immersion& im, double feed_per_tooth);

// The force's extremes over a revolution, sampled every `step_rad` of rotation (rounded to a whole number of steps
// per tooth pitch), the helix cut into slices that each lag by one step (its lag rounded to whole steps).
struct ForcePeaks {
  double resultant = 0.0;  // max |(F_x, F_y)| of the cutter (N)
  double tooth = 0.0;      // max |(F_x, F_y)| of one tooth (N)
  double normal = 0.0;     // max |F_y|, the force perpendicular to the feed (N)
  double axial = 0.0;      // max |F_z| (N)
};
ForcePeaks force_peaks(const SliceCutter& c, const Immersion& im, double feed_per_tooth,
                       double step_rad = 0.25 * 3.14159265358979323846 / 180.0);

}  // namespace polarcam::process
