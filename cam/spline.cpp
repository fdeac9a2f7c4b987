#include "cam/spline.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

#include "cam/error.hpp"

namespace polarcam {
namespace {

struct Cubic {  // a + b t + c t^2 + d t^3 per coordinate, t = u - u_i
  Vec2 a, b, c, d;
};

class Spline final : public Curve {
 public:
  Spline(std::vector<double> knots, std::vector<Cubic> segs, bool closed, std::string name)
      : Curve(knots.front(), knots.back(), closed, std::move(name)), knots_(std::move(knots)), segs_(std::move(segs)) {}

  CurvePoint eval(double u, int order) const override {
    size_t i = segment(u);
    double t = u - knots_[i];
    const Cubic& s = segs_[i];
    CurvePoint p;
    p.p = s.a + t * (s.b + t * (s.c + t * s.d));
    if (order >= 1) p.d1 = s.b + t * (2.0 * s.c + t * (3.0 * s.d));
    if (order >= 2) p.d2 = 2.0 * s.c + (6.0 * t) * s.d;
    if (order >= 3) p.d3 = 6.0 * s.d;
    return p;
  }

  std::vector<double> breakpoints() const override {
    return std::vector<double>(knots_.begin() + 1, knots_.end() - 1);
  }

 private:
  size_t segment(double u) const {
    auto it = std::upper_bound(knots_.begin(), knots_.end(), u);
    size_t i = (it == knots_.begin()) ? 0 : static_cast<size_t>(it - knots_.begin()) - 1;
    return std::min(i, segs_.size() - 1);
  }

  std::vector<double> knots_;
  std::vector<Cubic> segs_;
};

}  // namespace

CurvePtr make_spline(const std::vector<Vec2>& input, bool closed, const std::string& source_name) {
  std::vector<Vec2> pts = input;
  for (size_t i = 0; i < pts.size(); ++i)
    if (!std::isfinite(pts[i].x) || !std::isfinite(pts[i].y))
      throw InputError("point " + std::to_string(i + 1) + " is not a finite number");
  if (closed && pts.size() > 1 && norm(pts.front() - pts.back()) == 0.0) pts.pop_back();
  const size_t n = pts.size();
  if (n < (closed ? 3u : 2u))
    throw InputError(std::string(closed ? "a closed" : "an open") + " point list needs at least " +
                     (closed ? "3" : "2") + " distinct points, got " + std::to_string(n));
  const size_t nseg = closed ? n : n - 1;
  auto P = [&](size_t i) { return pts[i % n]; };
  std::vector<double> h(nseg), knots(nseg + 1, 0.0);
  for (size_t i = 0; i < nseg; ++i) {
    h[i] = norm(P(i + 1) - P(i));
    if (!(h[i] > 0.0))
      throw InputError("points " + std::to_string(i + 1) + " and " + std::to_string((i + 1) % n + 1) + " coincide");
    knots[i + 1] = knots[i] + h[i];
  }

  // Second derivatives M_i at the knots: h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (D_i - D_{i-1}).
  std::vector<Vec2> M(n, Vec2{});
  const size_t unknowns = closed ? n : (n >= 3 ? n - 2 : 0);
  if (unknowns > 0) {
    using SpMat = Eigen::SparseMatrix<double>;
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd rhs(unknowns, 2);
    for (size_t row = 0; row < unknowns; ++row) {
      size_t i = closed ? row : row + 1;  // knot index
      size_t im1 = closed ? (i + nseg - 1) % nseg : i - 1;
      double hl = h[im1], hr = h[i % nseg];
      Vec2 dr = (P(i + 1) - P(i)) / hr, dl = (P(i) - P(i + n - 1)) / hl;
      trip.emplace_back(row, row, 2.0 * (hl + hr));
      if (closed) {
        if (n > 2) {
          trip.emplace_back(row, (row + n - 1) % n, hl);
          trip.emplace_back(row, (row + 1) % n, hr);
        }
      } else {
        if (row > 0) trip.emplace_back(row, row - 1, hl);
        if (row + 1 < unknowns) trip.emplace_back(row, row + 1, hr);
      }
      rhs(row, 0) = 6.0 * (dr.x - dl.x);
      rhs(row, 1) = 6.0 * (dr.y - dl.y);
    }
    SpMat A(unknowns, unknowns);
    A.setFromTriplets(trip.begin(), trip.end());  // duplicates (n == 3 closed) are summed, as they should be
    Eigen::SimplicialLDLT<SpMat> solver(A);
    if (solver.info() != Eigen::Success) throw InputError("the spline system through the points is singular");
    Eigen::MatrixXd sol = solver.solve(rhs);
    for (size_t row = 0; row < unknowns; ++row) M[closed ? row : row + 1] = {sol(row, 0), sol(row, 1)};
  }

  std::vector<Cubic> segs(nseg);
  for (size_t i = 0; i < nseg; ++i) {
    Vec2 p0 = P(i), p1 = P(i + 1), m0 = M[i], m1 = M[(i + 1) % n];
    double hi = h[i];
    segs[i].a = p0;
    segs[i].b = (p1 - p0) / hi - (hi / 6.0) * (2.0 * m0 + m1);
    segs[i].c = 0.5 * m0;
    segs[i].d = (m1 - m0) / (6.0 * hi);
  }
  return std::make_shared<Spline>(std::move(knots), std::move(segs), closed,
                                  std::string(closed ? "closed" : "open") + " spline through " + std::to_string(n) +
                                      " points" + (source_name.empty() ? "" : " of " + source_name));
}

}  // namespace polarcam
