#pragma once
// A curve scaled by k about the origin of its frame: P(u) -> k P(u), same parameter, same breakpoints. What a
// machine that scales its tape's indices draws (Sec. 3.7 of A. Fahim's thesis (1983): the polar machine scales
// its radial axis, which scales the contour about the machine pole), and what the comparison measures it against.
#include "cam/curve.hpp"

namespace polarcam {

// Throws InputError unless k is finite and above zero.
CurvePtr scale_curve(CurvePtr curve, double k);

}  // namespace polarcam
