#pragma once
// The contour error of a path drawn by two servo axes (J. Peng 1989, Ch. 4; docs/feed-drives.md): each axis's
// model run on its reference sampled at T, the following error of each axis, the contour error e_c (the distance
// from the actual tool point to the reference path; Eq. 4.78 at steady state), its largest value and where the
// path leaves a tolerance. Cartesian machines: x, y in m; polar machines: r in m and theta in rad, the tool point
// (r cos theta, r sin theta).
#include <string>
#include <vector>

#include "machine/servo/drives_file.hpp"

namespace polarcam::servo {

// The reference positions of both axes sampled at t_k = k T (m, or rad for theta), from t = 0.
struct Reference {
  double T = 1e-3;
  std::vector<double> q[2];
  double quantum[2] = {0.0, 0.0};  // the positions' step (a tape's resolution), 0 when continuous
};

// J. Peng's test paths (Sec. 4.3, Fig. 4.28), Cartesian, traversed at a constant path speed `feed` (m/s):
// square: (0,0) -> (L,0) -> (L,L) -> (0,L) -> (0,0), L = 50 mm (one axis stops as the other starts);
// diamond: (-L,0) -> (0,L) -> (L,0) -> (0,-L) -> (-L,0), L = 50 mm (x keeps its speed at the top corner, y reverses);
// circle: x = R sin(w t), y = R cos(w t), R = 50 mm, w = feed/R (Eq. 4.104, 4.105), one turn.
// ramp > 0: each straight leg starts and ends with a linear speed ramp of that duration (Sec. 4.4.1); the circle
// ramps up at its start and down at its end. The reference holds its end for `hold` s after the path.
enum class TestPath { square, diamond, circle };
Reference test_path(TestPath path, double feed, double T, double ramp = 0.0, double hold = 0.2);

// A cubic Hermite segment in the normalised time s in [0, 1] (Sec. 4.4.3): r*(s) = A* (s^3, s^2, s, 1)^T with
// A* = R* B*^-1 (Eq. 4.132-4.135), R* = (r(t0), r'(t0) dt, r(t1), r'(t1) dt); the segment lasts dt.
struct SplineSegment {
  double A[2][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}};  // rows x, y; columns s^3, s^2, s, 1 (m)
  double dt = 0.0;                                // s
};
SplineSegment hermite_segment(const double p0[2], const double v0[2], const double p1[2], const double v1[2], double dt);

// Corner blending of the square and the diamond (Sec. 4.4.3): each corner replaced by cubic splines from `reach`
// before the corner along the incoming leg to `reach` after it along the outgoing one, at the path speed at both
// ends (the segment lasts 2 reach / feed). One segment (Case 1), or two (Case 2): through the point 1/100 of the
// way from the corner to the middle of the ends, with the mean of the two legs' velocities there.
struct CornerSpline {
  double corner[2] = {0, 0};   // m
  std::vector<SplineSegment> segments;
};
struct SplinedPath {
  Reference reference;
  std::vector<CornerSpline> corners;   // in the order the path meets them
};
// reach: J. Peng's 1 mm on each axis on the diamond is sqrt(2) mm along the legs.
SplinedPath test_path_with_splines(TestPath path, double feed, double T, int segments, double reach, double hold = 0.2);
TestPath parse_test_path(const std::string& name);  // InputError naming --path
const char* to_string(TestPath p);

// Following error of one axis at steady speed: the time average of X_r - X_a (sign of the motion: positive is a
// lag) over the longest stretch on which the reference's speed (averaged over 100 samples) stays within 0.1 % of
// one value (or within 1.5 quanta per 100 samples for a stepped reference), less the model's settling time (10
// time constants of its slowest mode).
struct SteadyError {
  bool found = false;
  double speed = 0.0;          // the stretch's reference speed (m/s or rad/s, signed)
  double error = 0.0;          // m or rad
  double error_counts = 0.0;   // encoder counts
  double t_begin = 0.0, t_end = 0.0;  // the stretch averaged (s)
};

struct Interval {
  double t_begin = 0.0, t_end = 0.0;  // s
  double s_begin = 0.0, s_end = 0.0;  // arc length along the reference path (m)
  double max_abs_error = 0.0;         // m
};

struct ServoOptions {
  double cutting_torque[2] = {0.0, 0.0};  // constant T_c on each motor shaft (N m)
  double tolerance = 0.05e-3;             // m, contour error allowed
};

struct ContourResult {
  bool polar = false;
  double T = 1e-3;
  std::vector<double> t;                  // s
  std::vector<double> ref[2], act[2];     // axis positions (m or rad)
  std::vector<double> current[2];         // armature current (A)
  std::vector<double> ref_xy[2], act_xy[2];  // tool point (m)
  std::vector<double> s;                  // arc length of the reference tool point along its path (m)
  std::vector<double> e_c;                // contour error (m): positive to the right of the motion (Eq. 4.78)
  SteadyError steady[2];
  double max_abs_contour_error = 0.0;     // m
  double max_at_t = 0.0, max_at_s = 0.0, max_at_x = 0.0, max_at_y = 0.0;
  double max_current[2] = {0.0, 0.0};     // A, largest |I_a|
  // the contour error at steady speed: its mean over the time both axes are steady (their stretches overlap),
  // e.g. the straight-line error of mismatched axes (Eq. 4.91); not found when they do not overlap
  bool steady_contour_found = false;
  double steady_contour_error = 0.0;      // m
  double tolerance = 0.0;
  std::vector<Interval> out_of_tolerance;
  bool within_tolerance() const { return out_of_tolerance.empty(); }
};

// Runs both axes on the reference and measures the contour error.
ContourResult run_contour(const Drives& drives, const Reference& ref, const ServoOptions& opt = {});

// The signed distance from p to the polyline `path` (points pts[i] = (x[i], y[i])) over the segments i0..i1-1:
// positive to the right of the direction of travel. Returns the distance and sets `at` to the arc-length
// parameter index (segment index + fraction).
double signed_distance(const std::vector<double>& x, const std::vector<double>& y, size_t i0, size_t i1, double px,
                       double py, double& at);

}  // namespace polarcam::servo
