// Point in polygon with CGAL's exact predicates (CGAL stays in this translation unit and area_check.cpp).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "optimize/pole_objective.hpp"

namespace polarcam {

struct ContourInside::Impl {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<K::Point_2> pts;
};

ContourInside::ContourInside(std::vector<Vec2> polygon) : poly_(std::move(polygon)), impl_(std::make_unique<Impl>()) {
  if (poly_.size() < 3) throw std::invalid_argument("ContourInside: a polygon needs three points");
  for (const Vec2& p : poly_) impl_->pts.emplace_back(p.x, p.y);
}

ContourInside::~ContourInside() = default;

bool ContourInside::inside(Vec2 p) const {
  const auto side = CGAL::bounded_side_2(impl_->pts.begin(), impl_->pts.end(), Impl::K::Point_2(p.x, p.y), Impl::K());
  return side != CGAL::ON_UNBOUNDED_SIDE;
}

double ContourInside::boundary_distance(Vec2 p) const {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < poly_.size(); ++i) {
    const Vec2 a = poly_[i], b = poly_[(i + 1) % poly_.size()], d = b - a;
    const double l2 = dot(d, d);
    const double s = l2 > 0.0 ? std::clamp(dot(p - a, d) / l2, 0.0, 1.0) : 0.0;
    best = std::min(best, norm(p - (a + s * d)));
  }
  return best;
}

}  // namespace polarcam
