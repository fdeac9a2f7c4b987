#pragma once
// Theta-rho polylines: the paths polar sand tables (Sisyphus, Oasis, Dune Weaver, Sandify's exports) draw.
// A pattern is a list of vertices (theta, rho): theta in radians, cumulative (it may exceed 2 pi and may
// decrease), rho a distance from the pole. Consecutive vertices are joined by the segment that is linear in
// theta and rho, the motion the tables make (each segment is a piece of an Archimedean spiral; a segment with
// equal thetas is a radial line, one with equal rhos an arc about the pole). A segment may start or end at the
// pole (rho = 0): the ball crosses the centre while the arm keeps its own angle.
//
// As a Curve the path is P(u) = rho(u) (cos theta(u), sin theta(u)) in metres about the pole, u in [0, n - 1]
// for n vertices, vertex k at u = k, linear in theta and rho on each [k, k + 1]; the vertices are breakpoints.
// Consecutive equal vertices are not allowed (the readers merge them).
#include <cstddef>
#include <string>
#include <vector>

#include "cam/curve.hpp"

namespace polarcam {

struct ThetaRho {
  double theta = 0.0;  // rad, cumulative
  double rho = 0.0;    // m from the pole (>= 0)
};

class ThetaRhoPath final : public Curve {
 public:
  // `v` has at least two vertices, rho >= 0, every value finite, no two consecutive vertices equal; `closed`
  // when the last vertex is the first one's point (same rho, theta a whole number of turns away).
  ThetaRhoPath(std::vector<ThetaRho> v, bool closed, std::string name);

  CurvePoint eval(double u, int order) const override;
  std::vector<double> breakpoints() const override;

  const std::vector<ThetaRho>& vertices() const { return v_; }
  // Segment k (0 .. n - 2) and the fraction f in [0, 1] along it for parameter u.
  void locate(double u, size_t& k, double& f) const;

 private:
  std::vector<ThetaRho> v_;
};

// Builds a theta-rho path, checking the vertices (InputError naming the vertex, counted from 1). A closed path
// is detected when the last vertex is at the first one's place (rho equal within 1e-12 m, theta a whole number
// of turns away within 1e-9 rad, or both at the pole).
CurvePtr make_theta_rho_path(std::vector<ThetaRho> v, std::string name);

// The theta-rho path a curve is, or nullptr.
const ThetaRhoPath* as_theta_rho_path(const Curve& c);

// Arc length of the segment from a to b (the Archimedean spiral piece), by the closed form.
double theta_rho_segment_length(const ThetaRho& a, const ThetaRho& b);

}  // namespace polarcam
