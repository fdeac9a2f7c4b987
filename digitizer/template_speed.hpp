#pragma once
// The template digitizer's contouring speed (A. Fahim's thesis, Sec. 2.2 and 3.5, Eq. 3.1-3.4, Fig. 3.2;
// docs/template-digitizer.md). Two rollers of radius R_r pinch a template of thickness H; the driven roller G
// sits at the carriage centre (the tool centre), the pressure roller G' on the other face. An electric
// differential keeps the sum of the two roller speeds at 2 V_t (Eq. 3.2), so where the template curves the
// carriage speed v departs from V_t. With the template outline's radius of curvature rho at G's contact point,
// rho* = rho / H, R_r* = R_r / H, v* = v / V_t:
//   Eq. 3.3a (centre of curvature on G's side):      v* = 2 (rho* - R_r*) / (2 rho* + 1)
//   Eq. 3.3b (centre of curvature on the other side): v* = 2 (rho* + R_r*) / (2 rho* - 1)
// The thesis prints both without the factor 2 of Eq. 3.2; with it, v* -> 1 on a straight template, so V_t is the
// straight-line speed. Both cases are one analytic function of the signed curvature c = H kappa (kappa > 0 when
// the centre of curvature lies on G's side): v* = 2 (1 - R_r* c) / (2 + c).
// The carriage can follow the template while G keeps moving, rho* > R_r* on G's side (c < 1 / R_r*), and while
// G' fits on the template's concave face, rho* >= 1 + R_r* on the other side (c >= -1 / (1 + R_r*)).
#include <memory>
#include <vector>

#include "cam/curve.hpp"
#include "digitizer/chebyshev.hpp"
#include "digitizer/speed_profile.hpp"

namespace polarcam {

// Where the centre of curvature lies relative to the driven roller G.
enum class CurvatureSide { roller, other };  // Eq. 3.3a, Eq. 3.3b

// The corrected Eq. 3.3: v / V_t for rho* = rho / H (> 0, may be +infinity) and R_r* = R_r / H.
double template_v_star(double rho_star, double rr_star, CurvatureSide side);
// The same as a function of the signed nondimensional curvature c = H kappa (+ toward G): 2 (1 - R_r* c) / (2 + c).
double template_v_star_curvature(double c, double rr_star);
// d v* / d c = -2 (2 R_r* + 1) / (2 + c)^2.
double template_v_star_slope(double c, double rr_star);
// The range of c the roller pair can track: [c_min, c_max), c_min = -1 / (1 + R_r*), c_max = 1 / R_r*.
double template_c_min(double rr_star);
double template_c_max(double rr_star);

struct TemplateSpec {
  double thickness = 0.0;      // H, m (> 0)
  double roller_radius = 0.0;  // R_r, m (> 0)
  int roller_sign = +1;        // the driven roller G: +1 on the left of the direction of travel, -1 on the right
};

// One point of the path and the template speed there.
struct TemplatePoint {
  double s = 0.0;             // arc length along the path from its start, m
  Vec2 p;                     // the path point (for a tool path: the machine frame)
  double c = 0.0;             // H kappa of the template outline, + when the centre of curvature is on G's side
  double radius_m = 0.0;      // |rho| = H / |c| (infinity where the template is straight)
  CurvatureSide side = CurvatureSide::roller;
  double v_star = 1.0;        // v / V_t
  double speed_mps = 0.0;     // V_t v*
};

struct TemplateSpeedRange {
  TemplatePoint slowest, fastest;
  TemplatePoint worst;        // largest |v* - 1| (the slowest or the fastest)
};

// The speed profile v(s) = V_t v*(c(s)) along a path, with t(s) = integral ds / v. The path may be the template
// outline offset by `offset` (signed, + left of travel, as cam::ToolPath): the template's curvature is recovered
// from the path's, kappa = kappa_path / (1 + offset kappa_path). On pieces between the path's breakpoints (bisected
// until converged) 1/v, ds/du and c are Chebyshev series of degree 16 whose tails are below 1e-14 of their size;
// t(s) is their integral, relative error about 1e-13 (well under a nanosecond for tapes shorter than hours).
class TemplateSpeed final : public SpeedProfile {
 public:
  struct Piece {
    double s0 = 0.0, t0 = 0.0;  // arc length and time at the piece start
    double len = 0.0;
    Cheb S, T, C, G;            // arc length and time from the piece start, c, ds/dt; on t in [-1, 1]
  };
  TemplateSpeed(std::vector<Piece> pieces, std::vector<double> kinks, TemplateSpeedRange range, double v_t,
                double rr_star, double own_length, double length);

  double time_at(double s) const override;
  double speed_at(double s) const override;
  double accel_at(double s) const override;
  std::vector<double> kinks() const override { return kinks_; }

  const TemplateSpeedRange& range() const { return range_; }
  double set_speed() const { return v_t_; }  // V_t, the speed on a straight template

 private:
  std::pair<size_t, double> locate(double s) const;  // piece and t at the path's arc length s
  std::vector<Piece> pieces_;
  std::vector<double> kinks_;
  TemplateSpeedRange range_;
  double v_t_, rr_star_;
  double scale_;  // own arc length per arc length of the caller's path (1 within rounding)
};

// Builds the profile for `path` (arc length `length` as the caller's track measured it). Throws InputError,
// naming the place, where the template has a corner or curves more tightly than the rollers can follow, or when
// the total time exceeds what a tape holds.
std::shared_ptr<const TemplateSpeed> make_template_speed(const Curve& path, double offset, double v_t,
                                                         const TemplateSpec& spec, double length);

}  // namespace polarcam
