// CGAL lives in this translation unit only (it is slow to compile); see area_check.hpp.
#include "metrics/area_check.hpp"

#include <CGAL/Arr_circle_segment_traits_2.h>
#include <CGAL/Arr_curve_data_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <cmath>
#include <deque>
#include <map>
#include <numbers>
#include <stdexcept>

namespace polarcam {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = K::FT;
using Base = CGAL::Arr_circle_segment_traits_2<K>;
// Each x-monotone piece carries how many times the cycle runs along it from left to right (minus right to left);
// overlapping pieces add up.
struct Add {
  int operator()(int a, int b) const { return a + b; }
};
using Traits = CGAL::Arr_curve_data_traits_2<Base, int, Add>;
using Arr = CGAL::Arrangement_2<Traits>;

struct RPoint {
  FT x, y;
};

// A rational point on the unit circle within about 1e-16 rad of angle phi (stereographic parametrisation).
RPoint unit(double phi) {
  phi = std::remainder(phi, 2.0 * std::numbers::pi);
  const bool flip = std::abs(phi) > 0.5 * std::numbers::pi;
  if (flip) phi = std::remainder(phi + std::numbers::pi, 2.0 * std::numbers::pi);
  const FT t(std::tan(0.5 * phi));
  const FT d = FT(1) + t * t;
  RPoint p{(FT(1) - t * t) / d, FT(2) * t / d};
  if (flip) p = {-p.x, -p.y};
  return p;
}

using XCurves = std::vector<Traits::X_monotone_curve_2>;

// Adds the x-monotone parts of a curve, each with +1 when the cycle runs along it from left to right.
void add_curve(XCurves& xcvs, const Base::Curve_2& c) {
  Base base;
  std::vector<boost::variant<Base::Point_2, Base::X_monotone_curve_2>> parts;
  base.make_x_monotone_2_object()(c, std::back_inserter(parts));
  for (auto& p : parts)
    if (const auto* x = boost::get<Base::X_monotone_curve_2>(&p)) xcvs.emplace_back(*x, x->is_directed_right() ? 1 : -1);
}

void add_segment(XCurves& xcvs, const K::Point_2& a, const K::Point_2& b) {
  if (a != b) add_curve(xcvs, Base::Curve_2(K::Segment_2(a, b)));
}

K::Point_2 exact_point(const Vec2& v) { return K::Point_2(FT(v.x), FT(v.y)); }

// The integral of |winding number| of the cycle made of the curves.
double winding_area(XCurves& xcvs);

}  // namespace

double area_error_cgal(const std::vector<Vec2>& polyline, const std::vector<StairNode>& nodes, double dr,
                       double dtheta, int64_t steps_per_rev) {
  if (polyline.size() < 2 || nodes.empty()) throw std::invalid_argument("area_error_cgal: empty input");
  XCurves xcvs;
  auto node = [&](const StairNode& s) {
    const int64_t m = steps_per_rev > 0 ? ((s.m % steps_per_rev) + steps_per_rev) % steps_per_rev : s.m;
    const RPoint u = unit(static_cast<double>(m) * dtheta);
    const FT rho = FT(dr) * FT(static_cast<double>(s.n));
    return K::Point_2(rho * u.x, rho * u.y);
  };

  for (size_t i = 0; i + 1 < polyline.size(); ++i) add_segment(xcvs, exact_point(polyline[i]), exact_point(polyline[i + 1]));
  add_segment(xcvs, exact_point(polyline.back()), node(nodes.back()));
  for (size_t k = nodes.size() - 1; k > 0; --k) {
    const StairNode& a = nodes[k];
    const StairNode& b = nodes[k - 1];
    const K::Point_2 pa = node(a), pb = node(b);
    if (a.m == b.m || pa == pb) {
      add_segment(xcvs, pa, pb);
    } else {
      if (a.n != b.n) throw std::invalid_argument("area_error_cgal: consecutive nodes differ in both axes");
      if (a.n == 0) continue;  // at the pole
      const FT rho = FT(dr) * FT(static_cast<double>(a.n));
      const K::Circle_2 circ(K::Point_2(0, 0), rho * rho, b.m > a.m ? CGAL::COUNTERCLOCKWISE : CGAL::CLOCKWISE);
      add_curve(xcvs, Base::Curve_2(circ, Base::Point_2(pa.x(), pa.y()), Base::Point_2(pb.x(), pb.y())));
    }
  }
  add_segment(xcvs, node(nodes.front()), exact_point(polyline.front()));
  return winding_area(xcvs);
}

double area_error_cgal_cartesian(const std::vector<Vec2>& polyline, const std::vector<XYNode>& nodes, double blu) {
  if (polyline.size() < 2 || nodes.empty()) throw std::invalid_argument("area_error_cgal_cartesian: empty input");
  XCurves xcvs;
  const FT b(blu);
  auto node = [&](const XYNode& s) {
    return K::Point_2(b * FT(static_cast<double>(s.i)), b * FT(static_cast<double>(s.j)));
  };
  for (size_t i = 0; i + 1 < polyline.size(); ++i) add_segment(xcvs, exact_point(polyline[i]), exact_point(polyline[i + 1]));
  add_segment(xcvs, exact_point(polyline.back()), node(nodes.back()));
  for (size_t k = nodes.size() - 1; k > 0; --k) {
    const XYNode& p = nodes[k];
    const XYNode& q = nodes[k - 1];
    if (p.i != q.i && p.j != q.j) throw std::invalid_argument("area_error_cgal_cartesian: a diagonal step");
    add_segment(xcvs, node(p), node(q));
  }
  add_segment(xcvs, node(nodes.front()), exact_point(polyline.front()));
  return winding_area(xcvs);
}

namespace {

double winding_area(XCurves& xcvs) {
  Arr arr;
  CGAL::insert(arr, xcvs.begin(), xcvs.end());

  // winding numbers: zero in the unbounded face; crossing a half-edge from its left face to its right face
  // subtracts the number of times the cycle runs along it
  std::map<const void*, int> wind;
  std::deque<Arr::Face_const_handle> queue;
  Arr::Face_const_handle outer = arr.unbounded_face();
  wind[&*outer] = 0;
  queue.push_back(outer);
  auto visit_ccb = [&](Arr::Ccb_halfedge_const_circulator first, int w) {
    auto h = first;
    do {
      const int flow = h->curve().data() * (h->direction() == CGAL::ARR_LEFT_TO_RIGHT ? 1 : -1);
      Arr::Face_const_handle g = h->twin()->face();
      if (wind.emplace(&*g, w - flow).second) queue.push_back(g);
    } while (++h != first);
  };
  while (!queue.empty()) {
    Arr::Face_const_handle f = queue.front();
    queue.pop_front();
    const int w = wind[&*f];
    for (auto c = f->outer_ccbs_begin(); c != f->outer_ccbs_end(); ++c) visit_ccb(*c, w);
    for (auto c = f->inner_ccbs_begin(); c != f->inner_ccbs_end(); ++c) visit_ccb(*c, w);
  }

  auto ccb_area = [&](Arr::Ccb_halfedge_const_circulator first) {
    double a = 0.0;
    auto h = first;
    do {
      const auto& ps = h->source()->point();
      const auto& pt = h->target()->point();
      const double sx = CGAL::to_double(ps.x()), sy = CGAL::to_double(ps.y());
      const double tx = CGAL::to_double(pt.x()), ty = CGAL::to_double(pt.y());
      const auto& cv = h->curve();
      if (cv.is_circular()) {
        const auto circ = cv.supporting_circle();
        const double cx = CGAL::to_double(circ.center().x()), cy = CGAL::to_double(circ.center().y());
        const double r2 = CGAL::to_double(circ.squared_radius());
        const double ux = sx - cx, uy = sy - cy, vx = tx - cx, vy = ty - cy;
        const double sweep = std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
        a += 0.5 * (cx * (ty - sy) - cy * (tx - sx)) + 0.5 * r2 * sweep;
      } else {
        a += 0.5 * (sx * ty - sy * tx);
      }
    } while (++h != first);
    return a;
  };
  double total = 0.0;
  for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
    if (f->is_unbounded()) continue;
    const auto it = wind.find(&*f);
    if (it == wind.end()) throw std::logic_error("area_error_cgal: a face was not reached");
    if (it->second == 0) continue;
    double a = 0.0;
    for (auto c = f->outer_ccbs_begin(); c != f->outer_ccbs_end(); ++c) a += ccb_area(*c);
    for (auto c = f->inner_ccbs_begin(); c != f->inner_ccbs_end(); ++c) a += ccb_area(*c);
    total += std::abs(it->second) * a;
  }
  return total;
}

}  // namespace
}  // namespace polarcam
