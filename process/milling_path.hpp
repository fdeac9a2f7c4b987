#pragma once
// The milling force along a contour (docs/process.md, "Milling along a contour"): the end mill's centre follows the
// tool path at the cutter's radius R from the contour; a constant radial width a of stock lies beyond the contour
// on the side away from the tool. At each point the engaged angle psi follows from the path's curvature: the
// cutter circle (radius R about the centre, which runs on a circle of radius rho_c) meets the stock's boundary,
// the contour's own offset by a (radius rho + a on a convex stretch, rho - a on a concave one):
//   convex (the contour bulges towards the tool; rho = rho_c - R):
//     cos psi = (rho_c^2 + R^2 - (rho + a)^2) / (2 rho_c R)
//   concave (rho = rho_c + R):
//     cos psi = ((rho - a)^2 - rho_c^2 - R^2) / (2 rho_c R),   psi = pi when a >= rho,
// both acos(1 - a/R) on a straight stretch; the engaged angle grows on concave stretches and shrinks on convex
// ones. The edge's feed per tooth is the centre's scaled by rho_m / rho_c, rho_m the radius of the middle of the
// cut's width (rho +- a/2): faster than the centre inside an arc, slower outside.
// The mode follows from the side the material is on and the spindle's direction: a clockwise (M03) cutter with
// the material on the left of its travel mills up (conventional), with the material on its right down (climb);
// a counter-clockwise cutter the other way round.
#include <vector>

#include "cam/curve.hpp"
#include "process/milling_force.hpp"

namespace polarcam::process {

// The engaged angle (rad, in [0, pi]) of a cutter of radius R taking a radial width a, its centre on a path of
// signed curvature kappa_c (1/m, positive turning left); material_left: the stock is on the left of the travel.
double engaged_angle(double R, double a, double kappa_c, bool material_left);
// The edge's feed per tooth over the centre's (1 on a straight stretch).
double edge_feed_scale(double R, double a, double kappa_c, bool material_left);
MillingMode milling_mode(bool material_left, bool clockwise);

struct MillingPathSpec {
  SliceCutter cutter;              // its radius is the tool path's offset
  double radial_width_m = 0.0;     // a, the stock beyond the contour
  double spindle_speed_rad_s = 0.0;
  int tool_side = 1;               // the tool centre left (+1) or right (-1) of the travel; the stock on the other
  bool clockwise = true;           // the spindle's direction seen from the spindle (M03)
  int stations = 2000;             // points along the path (at least 2 per smooth piece, both ends of each)
};

// Throws InputError naming the field.
void check_milling_path_spec(const MillingPathSpec& s);

// One point of the path: where it is, the engagement, and the force per metre of the centre's feed per tooth
// (the forces are proportional to it).
struct MillingStation {
  double s = 0.0;                // m, arc length of the tool path
  double u = 0.0;                // the path's parameter
  double curvature = 0.0;        // 1/m, the tool path's, signed (left +)
  double engaged_angle = 0.0;    // rad
  double feed_scale = 1.0;       // the edge's feed per tooth over the centre's
  Immersion immersion;           // entry and exit angles for the mode
  CutterForce mean;              // N per m of feed per tooth, the feed frame of milling_force.hpp
  ForcePeaks peaks;              // N per m of feed per tooth
};

// The force on the tool at a point and a speed, in the path's frame.
struct MillingForceAt {
  double feed_per_tooth_m = 0.0;     // f_t of the centre, V / (N n)
  double engaged_angle_rad = 0.0;
  double feed_force_N = 0.0;         // the mean force against the travel (resisting the feed: positive)
  double normal_force_N = 0.0;       // the mean force pushing the tool away from the material (positive)
  double axial_force_N = 0.0;        // the mean axial force
  double mean_resultant_N = 0.0;     // |(feed, normal)| of the mean
  double peak_resultant_N = 0.0;     // the largest |(F_x, F_y)| over a revolution
  double peak_tooth_N = 0.0;         // the largest force on one tooth
  double peak_normal_N = 0.0;        // the largest force perpendicular to the feed
};

class MillingPath {
 public:
  // The stations along `path` (a tool-centre path, arc length from its start). Throws InputError for a bad spec.
  MillingPath(const Curve& path, const MillingPathSpec& spec);

  const MillingPathSpec& spec() const { return spec_; }
  MillingMode mode() const { return mode_; }
  double length() const { return length_; }
  // In order of s; at a joint of the path's smooth pieces two stations share s (one for each side).
  const std::vector<MillingStation>& stations() const { return stations_; }
  // f_t = V / (N n), n the spindle's revolutions per second.
  double feed_per_tooth(double V) const;
  // The inverse: the speed for a feed per tooth.
  double speed_for_feed_per_tooth(double f_t) const;
  MillingForceAt at_station(size_t i, double V) const;
  // Between stations the forces per feed are interpolated linearly in s (beyond the ends: the end stations').
  MillingForceAt at(double s, double V) const;

 private:
  MillingForceAt from(const CutterForce& mean, const ForcePeaks& peaks, double engaged, double V) const;
  MillingPathSpec spec_;
  MillingMode mode_ = MillingMode::up;
  double length_ = 0.0;
  std::vector<MillingStation> stations_;
};

}  // namespace polarcam::process
