#pragma once
// The deviation of a machine's quasi-static path from the tool path (docs/area-error.md): the largest distance
// from a point of the machine path to the tool path (one-sided: machine path to contour), the same for the polar
// staircase (radial segments and arcs about the pole) and the Cartesian one (axis-aligned unit segments).
//
// The machine path is fed piece by piece in order. Each piece is sampled at its end (its start is the previous
// piece's end). The distance changes at most as fast as the point moves (it is 1-Lipschitz), so nothing inside a
// piece of length L whose ends are at distances d_a and d_b exceeds (d_a + d_b + L) / 2: where that bound does not
// beat the largest value found so far, the piece is done. Otherwise it is sampled at its middle too; the distance
// along a piece is smooth while the nearest point of the tool path moves smoothly with it, and then the largest of
// the three samples is the maximum unless the distance has a maximum inside the piece. A piece is searched for its
// true maximum (golden section on the piece) when the parabola through the three samples has its maximum inside
// the piece, or when the nearest points of its ends and middle lie on different smooth stretches of the path (a
// corner of the path between them, where the distance may have a kink), unless even the Lipschitz bound cannot
// beat the largest value found so far.
//
// Where the foot tracker runs on its local model (below), a node is not searched for its foot when a point of the
// model near it (predicted along the tangent from the last node's, with a Newton step every few nodes) is no
// farther from it than the largest distance so far: any point of the path bounds the distance from above, so the
// node cannot be where the largest is, and the bound serves the tests of its pieces. Where a piece's middle must be
// sampled, its ends' feet are found first and the tests made again, so the middle and the search inside the piece
// judge by the distances themselves. A caller that assigns steps by their feet names the parameters where that
// assignment changes (set_exact_near); near them the foot is always found.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "cam/curve.hpp"

namespace polarcam {

// A piece of a quasi-static path: a straight segment from a to b, or an arc about the origin of radius rho from
// angle phi0 to phi1 whose end the caller puts in b too.
struct StairPiece {
  bool arc = false;
  Vec2 a, b;
  double rho = 0, phi0 = 0, phi1 = 0;
  Vec2 at(double tau) const {
    if (!arc) return a + tau * (b - a);
    const double p = phi0 + tau * (phi1 - phi0);
    return {rho * std::cos(p), rho * std::sin(p)};
  }
  double length() const {  // (a bound's length: the root of the square, not the library's slower hypot)
    const Vec2 d = b - a;
    return arc ? rho * std::abs(phi1 - phi0) : std::sqrt(dot(d, d));
  }
};

// Foot points of a moving point on a curve: the parameter of the nearest point of the curve, searched near the
// previous one. The window (`reach` of path either side) is sampled, moved on while the nearest sample is at its
// edge, and the best sample refined by Newton's method on (C(u) - p) . C'(u) = 0 within its neighbourhood, or by
// golden-section search where Newton does not settle (at a corner of the path).
//
// Once it has found a first foot it tracks: Newton's method straight from the previous foot, accepted when the
// window holds no corner of the path (a breakpoint, or the seam of a closed path), stays away from the ends of an
// open path, and the path's curvature at the foot is small enough (|kappa| (d + reach) <= 1/2) that the squared
// distance is convex across the window, so that the stationary point Newton finds is the window's only minimum.
// Otherwise, the window search.
//
// Where the grid is fine, tracking runs on a local model of the curve instead of the curve itself: its cubic
// Taylor polynomial about an anchor, C(u_a + s) = C + C' s + C'' s^2 / 2 + C''' s^3 / 6, on a stretch |s| <= h
// that holds no corner. A stretch is taken only when the polynomial agrees with the curve at s = +-2h to within
// four units of rounding of a point of the curve (4 eps (|C| + its rounding scale)); its truncation error, of
// order s^4, is then a sixteenth of that on the stretch, below the rounding of an evaluation of the curve. It
// needs h to be at least four search windows (on the thesis's grid the curve bends too much for that and the
// curve is evaluated as before); each anchor costs three evaluations of the curve and serves the searches of
// many steps. The same acceptance tests apply (the window inside the stretch, Newton settling inside the window,
// the curvature bound).
class FootTracker {
 public:
  explicit FootTracker(const Curve& c) : FootTracker(c, true) {}
  // Parameter of the point of the curve nearest p, near `guess`; distance() is then |p - curve(u)|.
  double find(Vec2 p, double guess, double reach);
  double distance() const { return dist_; }
  // The path's curvature at the foot find() returned when it tracked (Newton's method from the guess, accepted in
  // the convex regime |kappa| (d + reach) <= 1/2); NaN after a window search.
  double curvature() const { return kappa_; }
  // An upper bound of p's distance to the curve, where the local model is tracking and the bound is at most
  // `limit`: the distance from p to the model's point predicted along the tangent from the last one, or one Newton
  // step from it every kPredictSteps calls (any point of the curve bounds the distance from above). True, with u
  // that point's parameter and distance() the bound, curvature() a bound of the curvature over the model's whole
  // stretch (NaN where it does not keep the convex regime); false, with nothing changed, where the model is not
  // tracking, the point leaves the stretch, the bound exceeds the limit, or the point lies near a parameter where the
  // exact foot matters (set_exact_near).
  bool bound_within(Vec2 p, double guess, double reach, double limit, double& u);
  // Parameters near which bound_within() declines (the bounds of a caller's segments of the path, where an
  // estimated foot might fall on the wrong side).
  void set_exact_near(std::vector<double> us) { exact_near_ = std::move(us); }
  // Testing: always the window search.
  void set_full_search(bool on) { full_ = on; }
  // Testing: never the local model (track on the curve itself); stretches of the model taken so far.
  void set_model(bool on) { model_on_ = on; }
  uint64_t anchors() const { return anchors_; }

 private:
  FootTracker(const Curve& c, bool);
  double wrap(double u) const {
    if (!closed_) return std::clamp(u, u0_, u1_);
    if (u0_ == 0.0 && u > 0.0 && u < u1_) return u;  // what the remainder gives, without the division
    return wrap_turn(u);
  }
  double wrap_turn(double u) const;  // u on the turn [u0, u1) of a closed path
  double d2(double u, Vec2 p) const;
  bool newton(Vec2 p, double lo, double hi, double& u, double& d2) const;
  bool track(Vec2 p, double guess, double reach, double& u);
  bool corner_in(double lo, double hi) const;
  // The curve to order 2 at u, remembered: a search ends where the next one starts (the foot it returns is the
  // next guess), so the point a search measured its distance at is the next search's first point.
  const CurvePoint& eval2(double u);
  // the local model (above)
  struct Model {
    bool ok = false;
    double uc = 0.0, h = 0.0;  // anchor (wrapped) and half-width of the stretch
    Vec2 p0, p1, p2, p3;       // C, C', C''/2, C'''/6 at the anchor
    double kappa_max = 0.0;    // a bound of the curvature on the stretch, |C''|max / |C'|min^2 (infinity: none)
    std::vector<double> exact; // offsets from the anchor of the parameters of set_exact_near() near the stretch
    // d0 + C(s) - C (d0 = C - p: the point's offset from p, nearby points formed first) and C'(s)
    Vec2 at(Vec2 d0, double s) const { return d0 + s * (p1 + s * (p2 + s * p3)); }
    Vec2 d1(double s) const { return p1 + s * (2.0 * p2 + 3.0 * s * p3); }
  };
  bool model_track(Vec2 p, double guess, double reach, double& u);
  // the last foot the model returned, and its offset from the anchor (the next search's start, without the
  // rounding of forming it again from the parameter)
  double last_u_ = std::numeric_limits<double>::quiet_NaN(), last_s_ = 0.0;
  // bound_within()'s predictor: the last estimate's node, C' / |C'|^2 at the last Newton step's estimate, and the
  // estimates left before the next Newton step (0: a Newton step next)
  static constexpr int kPredictSteps = 32;
  Vec2 pred_p_, pred_w_;
  int pred_left_ = 0;
  bool anchor(double u, double w);
  double offset(double u) const;  // u - the anchor, on the anchor's turn of a closed path
  const Curve& c_;
  Model m_;
  double h_good_ = 0.0;  // the last stretch accepted
  int model_off_ = 0;    // searches left before the model is tried again after a stretch was refused
  uint64_t anchors_ = 0;
  double memo_u_ = std::numeric_limits<double>::quiet_NaN();
  CurvePoint memo_{};
  double u0_, u1_;
  bool closed_;
  std::vector<double> breaks_;
  std::vector<double> exact_near_;
  bool tracking_ = false, full_ = false, model_on_ = true;
  double dist_ = 0.0, kappa_ = std::numeric_limits<double>::quiet_NaN();
};

class DeviationMeter {
 public:
  explicit DeviationMeter(const Curve& path);
  // The first node of the machine path; `reach`: how far from the previous foot point to search (a few cells).
  void start(Vec2 node, double reach);
  // The next piece, from the current node (piece.a) to the next (piece.b). Returns the foot parameters of its
  // ends, and of its middle where the middle was sampled (NaN where it was not).
  struct Feet {
    double a, m, b;
  };
  Feet piece(const StairPiece& p, double reach);  // (inline below: the usual piece is a few dozen operations)
  // The foot parameter of the middle of the piece just fed (for a piece whose middle piece() did not sample).
  double middle_foot(const StairPiece& p, double reach);

  double max() const { return max_; }
  Vec2 at() const { return at_; }  // the point of the machine path where the largest distance is
  uint64_t refined() const { return refined_; }  // pieces searched for an inside maximum
  void set_full_search(bool on) { ft_.set_full_search(on); }  // testing
  void set_model(bool on) { ft_.set_model(on); }              // testing
  uint64_t anchors() const { return ft_.anchors(); }          // testing
  // Testing: sample every piece's middle (no bound skips it); middles sampled so far.
  void set_every_middle(bool on) { every_middle_ = on; }
  uint64_t middles() const { return middles_; }
  // Testing: never bound a node's distance from above (every node's foot found); nodes bounded so far.
  void set_bounds(bool on) { bounds_on_ = on; }
  uint64_t bounded() const { return bounded_; }
  // Parameters near which a node's foot is always found, not estimated (FootTracker::set_exact_near).
  void set_exact_near(std::vector<double> us) { ft_.set_exact_near(std::move(us)); }

 private:
  void consider(double d, Vec2 p);
  bool breaks_between(double ua, double ub) const {
    if (ua > ub) std::swap(ua, ub);
    if (closed_ && ub - ua > 0.5 * span_) return true;  // across the seam of a closed path (a corner, perhaps)
    if (breaks_.empty()) return false;
    const auto it = std::upper_bound(breaks_.begin(), breaks_.end(), ua);
    return it != breaks_.end() && *it < ub;
  }
  // A piece's ends: their feet, distances (upper bounds where not exact) and the curvature there.
  struct Ends {
    double u_a, d_a, k_a;
    bool exact_a;
    double u_b = 0, d_b = 0, k_b = 0;
    bool exact_b = false;
  };
  // nothing inside the piece can beat (d_a + d_b + len) / 2 (the distance is 1-Lipschitz); nor, where both ends'
  // feet were tracked in the convex regime with no corner of the path between them, max(d_a, d_b) + len^2 / 8 times
  // the bound on the distance's second derivative along the piece: kappa / (1 - kappa d) <= 2 kappa from the path's
  // curvature (taken as twice the larger of the feet's, or the bound over a model's stretch), plus 1 / rho for an arc
  bool ends_done(const StairPiece& p, const Ends& e, double len) const {
    if (every_middle_) return false;
    if (!(0.5 * (e.d_a + e.d_b + len) > max_)) return true;
    if (std::isfinite(e.k_a) && std::isfinite(e.k_b) && !breaks_between(e.u_a, e.u_b)) {
      const double curv = 4.0 * std::max(e.k_a, e.k_b) + (p.arc ? 1.0 / p.rho : 0.0);
      if (std::max(e.d_a, e.d_b) + 0.125 * len * len * curv <= max_) return true;
    }
    return false;
  }
  void keep_end(const Ends& e, Vec2 pb) {
    u_ = e.u_b;
    d_node_ = e.d_b;
    k_node_ = e.k_b;
    node_exact_ = e.exact_b;
    node_ = pb;
  }
  // the foot of q found from `guess` (its parameter, distance and the curvature there), q considered for the largest
  void find_end(Vec2 q, double guess, double reach, double& u, double& d, double& k);
  // piece() where the ends' tests do not settle it: the ends' feet, the middle, the search inside
  Feet piece_rest(const StairPiece& p, double reach, Ends& e, double len);
  const Curve& c_;
  FootTracker ft_;
  std::vector<double> breaks_;
  double span_;
  bool closed_;
  // the last node: its foot, its distance (an upper bound of it where node_exact_ is false), the curvature there
  double u_ = 0.0, d_node_ = 0.0, k_node_ = std::numeric_limits<double>::quiet_NaN();
  bool node_exact_ = true;
  Vec2 node_;
  double max_ = 0.0;
  uint64_t bounded_ = 0;
  bool bounds_on_ = true;
  Vec2 at_;
  uint64_t refined_ = 0, middles_ = 0;
  bool every_middle_ = false;
};

inline bool FootTracker::bound_within(Vec2 p, double guess, double reach, double limit, double& u_out) {
  if (!tracking_ || full_ || !model_on_ || !m_.ok || model_off_ > 0) return false;
  const double gw = wrap(guess);
  const bool from_last = gw == last_u_;
  const Vec2 d0 = m_.p0 - p;
  double sn, ds;
  if (from_last && pred_left_ > 0) {
    // the point's parameter predicted from the last estimate along the tangent there: s + (p - p_last) . C' / |C'|^2
    // (no evaluation on the chain from node to node; its error, of order the curvature times the steps since the
    // last Newton step, only loosens the bound)
    ds = dot(p - pred_p_, pred_w_);
    sn = last_s_ + ds;
    --pred_left_;
  } else {
    // one Newton step on g(s) = (C(s) - p) . C'(s) = 0 from the last foot, on the polynomial (C - p first: nearby
    // points)
    const double s = from_last ? last_s_ : offset(gw);
    if (!(std::abs(s) < m_.h)) return false;
    const Vec2 q = m_.at(d0, s);
    const Vec2 c1 = m_.d1(s), c2 = 2.0 * m_.p2 + (6.0 * s) * m_.p3;
    const double dg = dot(c1, c1) + dot(q, c2);
    if (!(dg > 0.0)) return false;
    ds = -dot(q, c1) / dg;
    sn = s + ds;
    const Vec2 w = m_.d1(sn);  // C' at the estimate: the predictor's tangent
    pred_w_ = (1.0 / dot(w, w)) * w;
    pred_left_ = kPredictSteps;
  }
  if (!(std::abs(sn) < m_.h)) {  // the model holds to rounding on the stretch only
    pred_left_ = 0;
    return false;
  }
  const Vec2 qn = m_.at(d0, sn);
  const double b2 = dot(qn, qn);
  // near a parameter where the exact foot matters, the estimate (off by far less than its step) might not do
  bool near = false;
  if (!m_.exact.empty()) {
    const double margin =
        4.0 * std::abs(ds) + 64.0 * std::numeric_limits<double>::epsilon() * (std::abs(u0_) + std::abs(u1_));
    for (double e : m_.exact) near = near || std::abs(sn - e) <= margin;
  }
  if (!(b2 <= limit * limit) || near) {
    pred_left_ = 0;
    return false;
  }
  dist_ = std::sqrt(b2);
  kappa_ = m_.kappa_max * (dist_ + reach) <= 0.5 ? m_.kappa_max : std::numeric_limits<double>::quiet_NaN();
  u_out = wrap(m_.uc + sn);
  last_u_ = u_out;
  last_s_ = sn;
  pred_p_ = p;
  return true;
}

inline DeviationMeter::Feet DeviationMeter::piece(const StairPiece& p, double reach) {
  Ends e{u_, d_node_, k_node_, node_exact_};
  // The end node: where an upper bound of its distance cannot beat the largest distance so far, that bound (the
  // node cannot be where the largest is; the bounds below hold with it); otherwise its foot.
  if (bounds_on_ && ft_.bound_within(p.b, e.u_a, reach, max_, e.u_b)) {
    e.d_b = ft_.distance();
    e.k_b = ft_.curvature();
    ++bounded_;
  } else {
    find_end(p.b, e.u_a, reach, e.u_b, e.d_b, e.k_b);
    e.exact_b = true;
  }
  const double len = p.length();
  if (ends_done(p, e, len)) {
    keep_end(e, p.b);
    return {e.u_a, std::numeric_limits<double>::quiet_NaN(), e.u_b};
  }
  return piece_rest(p, reach, e, len);
}

}  // namespace polarcam
