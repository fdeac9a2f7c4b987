#pragma once
// The thesis's surrogate objective for pole placement (Sec. 4.5-4.7 of A. Fahim's thesis (1983),
// docs/area-error.md): the contour is cut into n segments; for each, N_R and N_theta are its radial and angular
// step counts, and with the penalty K / R_m, K = DeltaR / DeltaTheta (a length), applied where N_R > N_theta:
//   F_sum = sum |N_R + N_theta K/R_m|,  F_dif = sum |N_R - N_theta K/R_m|  (K/R_m -> 1 where N_R <= N_theta),
//   F1 = F_dif / F_sum                                                    (Eq. 4.5, 4.6, 4.10).
// Two forms:
//  - from step counts per segment (Eq. 4.5-4.6; R_m = distance of the segment's chord midpoint from the pole);
//  - from the chords of the piecewise-linear approximation (Eq. 4.13-4.15, as the program HOKJEV of App. E
//    computes it): N_R = |dr| / DeltaR, N_theta = |dtheta| / DeltaTheta of each chord, and where N_R >= N_theta
//    the penalised term N_theta K / R_m = (DeltaR / DeltaTheta^2) |integral of dtheta / r| along the chord
//    (R_m is then the mean radius in the sense of that integral). Chords with N_R = 0 or N_theta = 0 are left out,
//    as the listing does.
#include <vector>

#include "cam/curve.hpp"
#include "cam/vec2.hpp"

namespace polarcam {

struct F1Value {
  double F_sum = 0.0, F_dif = 0.0, F1 = 0.0;  // F1 = 0 when F_sum = 0 (no segment counted)
  int segments_used = 0;
};

// Points cutting a path into n segments of equal parameter span (the thesis's CUREVA: equal steps of x for the
// Cartesian test curves, of theta1 for the limacon), in the path's own frame.
std::vector<Vec2> segment_points(const Curve& path, int n);

// Eq. 4.15 on the chords between consecutive points (machine frame: the machine pole at the origin).
F1Value f1_chords(const std::vector<Vec2>& points, double dr, double dtheta);
// Same, with every point shifted by -pole first (points in the contour's frame, pole = O - O1).
F1Value f1_chords(const std::vector<Vec2>& points, Vec2 pole, double dr, double dtheta);

// Eq. 4.5-4.6 from step counts: radial[i], angular[i] are the steps of segment i, between points i and i + 1.
F1Value f1_counts(const std::vector<Vec2>& points, const std::vector<long long>& radial,
                  const std::vector<long long>& angular, double dr, double dtheta);

// |integral of dtheta / r| along the straight chord from a to b about the origin (closed form; 1/m).
double chord_inverse_radius_integral(Vec2 a, Vec2 b);

}  // namespace polarcam
