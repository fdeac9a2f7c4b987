#pragma once
// The named curves: the thesis's test contours (Eq. 4.18-4.20 of A. Fahim's thesis (1983)), the circle and the
// straight line, and the sand-table staples (Archimedean spiral, rose). All lengths in metres.
#include "cam/curve.hpp"

namespace polarcam {

// Circle of radius `radius` about `center`, u = angle about the centre in [0, 2 pi], counter-clockwise, closed.
CurvePtr make_circle(Vec2 center, double radius);

// Straight segment from `a` to `b`, u = distance from a in [0, |b - a|].
CurvePtr make_line(Vec2 a, Vec2 b);

// Witch of Agnesi y = 8 a^3 / (x^2 + 4 a^2) (Eq. 4.18), u = x in [x_from, x_to].
CurvePtr make_witch(double a, double x_from, double x_to);

// Serpentine y = a b x / (a^2 + x^2) (Eq. 4.20), u = x in [x_from, x_to].
CurvePtr make_serpentine(double a, double b, double x_from, double x_to);

// Limacon r1 = b + a cos(theta1) about the contour pole (Table 4.1, App. C), u = theta1 in [0, 2 pi], closed.
CurvePtr make_limacon(double a, double b);

// Archimedean spiral r1 = a + b theta1, u = theta1 in [t_from, t_to].
CurvePtr make_spiral(double a, double b, double t_from, double t_to);

// Rose r1 = a cos(k theta1) with k = p/q in lowest terms; closed over theta1 in [0, pi q] when p q is odd and
// [0, 2 pi q] otherwise.
CurvePtr make_rose(double a, int p, int q);

// Polar curve helper: P = rho(t) (cos t, sin t) from rho and its derivatives.
CurvePoint polar_point(double t, double rho, double rho1, double rho2, double rho3, int order);

}  // namespace polarcam
