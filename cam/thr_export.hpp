#pragma once
// Any path about the machine pole as a theta-rho polyline (cam/theta_rho_path.hpp): the vertices a polar sand
// table plays, each pair joined by the segment linear in theta and rho (a piece of an Archimedean spiral).
//
// The method.
//  1. The path is cut at its breakpoints (spline knots, joints of lines and arcs) and where it runs through the
//     pole: each piece is scanned at 64 points for local minima of rho, and every minimum is refined (golden
//     section on |P(u)|); a minimum closer to the pole than a thousandth of the tolerance is a pole crossing.
//  2. Theta is unwrapped continuously along each piece (samples closer than an eighth of a turn apart, refined
//     where the path turns faster) and from one piece to the next. Where the path touches the pole, the vertex is
//     put exactly at rho = 0 with the angle the path arrives along; the path leaves with the angle of its
//     outgoing direction, the nearest one to the arriving angle (a half turn, for a line through the pole, is
//     taken counter-clockwise). The two vertices at the pole form a segment in which the ball stays at the centre
//     and only the arm turns. A path that starts or ends at the pole takes the angle of its direction there.
//  3. Each piece is bisected adaptively in its parameter: a segment between the vertices of u_a and u_b is kept
//     when the distance between the spiral segment and the curve piece [u_a, u_b] is at most 0.98 of the
//     tolerance, measured both ways: from 33 points of the curve piece to the nearest point of the spiral and from
//     33 points of the spiral to the nearest point of the curve piece (each nearest point refined by a safeguarded
//     Newton iteration from the nearest sample, and every distance taken is one between two actual points, so
//     the refinement can only over-estimate). The 2 % margin covers the largest deviation falling between the
//     sample points. No segment turns the arm by more than a quarter turn, so that the distances measured are
//     between neighbouring pieces of the two paths (and never to another turn of a spiral).
// A circle about the pole, an Archimedean spiral about it and a radial line are represented exactly (a circle by
// 5 vertices, quarter turns; a spiral by segments of at most a quarter turn); a theta-rho path
// (as_theta_rho_path) is returned as its own vertices, unchanged.
#include <vector>

#include "cam/curve.hpp"
#include "cam/theta_rho_path.hpp"

namespace polarcam {

// The theta-rho vertices (theta in radians, unwrapped continuously along the path; rho in metres) of `path`,
// whose origin is the machine pole, such that every segment linear in theta and rho lies within `tolerance_m`
// of the piece of the path it replaces. Consecutive vertices are distinct. Throws InputError for a tolerance that
// is not a positive length, or a path that cannot be evaluated (a non-finite point).
std::vector<ThetaRho> to_theta_rho(const Curve& path, double tolerance_m);

}  // namespace polarcam
