#include "metrics/deviation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace polarcam {
namespace {
constexpr double kGolden = 0.6180339887498949;
}  // namespace

double FootTracker::wrap_turn(double u) const {
  const double span = u1_ - u0_;
  double v = std::fmod(u - u0_, span);
  if (v < 0) v += span;
  return u0_ + v;
}

double FootTracker::d2(double u, Vec2 p) const {
  const Vec2 q = c_.eval(wrap(u), 0).p - p;
  return dot(q, q);
}

FootTracker::FootTracker(const Curve& c, bool)
    : c_(c), u0_(c.u_begin()), u1_(c.u_end()), closed_(c.closed()), breaks_(c.breakpoints()) {}

bool FootTracker::corner_in(double lo, double hi) const {
  if (closed_) {
    const double span = u1_ - u0_;
    if (hi - lo >= span) return true;
    // the seam of a closed path may be a corner (a polygon starting at a vertex)
    const double a = wrap(lo), b = a + (hi - lo);
    if (b >= u1_) return true;
    lo = a, hi = b;
  }
  const auto it = std::upper_bound(breaks_.begin(), breaks_.end(), lo);
  return it != breaks_.end() && *it < hi;
}

const CurvePoint& FootTracker::eval2(double u) {
  if (!(u == memo_u_)) {
    memo_ = c_.eval(u, 2);
    memo_u_ = u;
  }
  return memo_;
}

bool FootTracker::track(Vec2 p, double guess, double reach, double& u_out) {
  CurvePoint c = eval2(wrap(guess));
  const double speed = std::sqrt(dot(c.d1, c.d1));
  if (!(speed > 0.0)) return false;
  const double w = reach / speed, lo = guess - w, hi = guess + w;
  if (!closed_ && (lo < u0_ || hi > u1_)) return false;  // near an end the nearest point may be the end itself
  if (corner_in(lo, hi)) return false;
  double u = guess;
  for (int it = 0; it < 8; ++it) {
    if (it > 0) c = eval2(wrap(u));
    const Vec2 q = c.p - p;
    const double s2 = dot(c.d1, c.d1), g = dot(q, c.d1), dg = s2 + dot(q, c.d2);
    if (!(dg > 0.0)) return false;
    const double du = -g / dg, un = u + du;
    if (!(un > lo && un < hi)) return false;
    u = un;
    if (std::abs(du) * std::sqrt(s2) <= 1e-9 * std::sqrt(dot(q, q)) + 1e-15) {
      // the window's only minimum: the squared distance along the arc length has the second derivative
      // 2 (1 - kappa d) > 0 throughout when |kappa| (d + reach) <= 1/2
      const double kappa = std::abs(cross(c.d1, c.d2)) / (s2 * std::sqrt(s2));
      const double d = norm(eval2(wrap(u)).p - p);
      if (!(kappa * (d + reach) <= 0.5)) return false;
      dist_ = d;
      kappa_ = kappa;
      u_out = wrap(u);
      return true;
    }
  }
  return false;
}

double FootTracker::offset(double u) const {
  double s = u - m_.uc;
  if (closed_) {
    const double span = u1_ - u0_;
    if (s > 0.5 * span)
      s -= span;
    else if (s < -0.5 * span)
      s += span;
  }
  return s;
}

bool FootTracker::anchor(double u, double w) {
  m_.ok = false;
  last_u_ = std::numeric_limits<double>::quiet_NaN();  // its offset was from the old anchor
  pred_left_ = 0;
  const CurvePoint c = c_.eval(u, 3);
  m_.uc = u;
  m_.p0 = c.p;
  m_.p1 = c.d1;
  m_.p2 = 0.5 * c.d2;
  m_.p3 = (1.0 / 6.0) * c.d3;
  const double tol = 4.0 * std::numeric_limits<double>::epsilon() * (norm(c.p) + c_.rounding_scale());
  const double h_min = 4.0 * w;
  double h = std::max(2.0 * h_good_, 4.0 * h_min);
  if (!closed_) h = std::min({h, u - u0_, u1_ - u});
  if (closed_) h = std::min(h, 0.125 * (u1_ - u0_));
  for (; h >= h_min; h *= 0.5) {
    if (corner_in(u - h, u + h)) continue;
    // the polynomial against the curve at twice the stretch (where that is on the curve)
    bool ok = true;
    for (double sg : {-1.0, 1.0}) {
      const double s = 2.0 * sg * h, su = u + s;
      if (!closed_ && (su < u0_ || su > u1_)) continue;
      const Vec2 m = m_.at(m_.p0, s);
      if (!(norm(m - c_.eval(wrap(su), 0).p) <= tol)) {
        ok = false;
        break;
      }
    }
    if (ok) {
      m_.h = h;
      m_.ok = true;
      // the curvature's bound on the stretch: |C' x C''| / |C'|^3 <= |C''| / |C'|^2, with |C''| and |C'| bounded
      // over |s| <= h from the polynomial's coefficients
      const double c2max = 2.0 * norm(m_.p2) + 6.0 * norm(m_.p3) * h;
      const double c1min = norm(m_.p1) - 2.0 * norm(m_.p2) * h - 3.0 * norm(m_.p3) * h * h;
      m_.kappa_max = c1min > 0.0 ? c2max / (c1min * c1min) : std::numeric_limits<double>::infinity();
      m_.exact.clear();
      for (double e : exact_near_) {
        const double s = offset(e);
        if (std::abs(s) <= 2.0 * h) m_.exact.push_back(s);
      }
      h_good_ = h;
      ++anchors_;
      return true;
    }
  }
  h_good_ = 0.0;
  return false;
}

bool FootTracker::model_track(Vec2 p, double guess, double reach, double& u_out) {
  if (model_off_ > 0) {
    --model_off_;
    return false;
  }
  const double gw = wrap(guess);
  const double r2 = reach * reach;
  double s = 0.0, s2_0 = 0.0;  // the window's centre, |C'|^2 there
  bool inside = false;
  if (m_.ok) {
    // the window |s' - s| < w = reach / |C'(s)| inside the stretch, w < h - |s|: squared, without a root or a
    // quotient; the last foot's own s where the guess is that foot
    s = gw == last_u_ ? last_s_ : offset(gw);
    const Vec2 c1 = m_.d1(s);
    const double room = m_.h - std::abs(s);
    s2_0 = dot(c1, c1);
    inside = room > 0.0 && r2 < room * room * s2_0;
  }
  if (!inside) {
    const double speed = norm(eval2(gw).d1);
    if (!(speed > 0.0)) return false;
    if (!anchor(gw, reach / speed)) {
      model_off_ = 256;
      return false;
    }
    s = 0.0;
    s2_0 = dot(m_.p1, m_.p1);
  }
  // Halley's method on g(s) = (C(s) - p) . C'(s) = 0 (Newton's, as in track(), with the curvature of g) on the
  // polynomial; C - p first (nearby points: exact). It stops once a step is below the tolerance, or once the error
  // left after a step, |g''^2 / (4 g'^2) - g''' / (6 g')| |ds|^3 (Halley's cubic convergence), is below a quarter
  // of it: from the previous foot that is one step. One quotient a step: Halley's step as g g' / (g'^2 - g g'' / 2).
  const double s0 = s;
  const Vec2 d0 = m_.p0 - p, c3 = 6.0 * m_.p3;
  for (int it = 0; it < 8; ++it) {
    const Vec2 q = m_.at(d0, s);
    const Vec2 c1 = m_.d1(s), c2 = 2.0 * m_.p2 + s * c3;
    const double s2 = dot(c1, c1), g = dot(q, c1), dg = s2 + dot(q, c2);
    if (!(dg > 0.0)) return false;
    const double g2 = 3.0 * dot(c1, c2) + dot(q, c3), g3 = 4.0 * dot(c1, c3) + 3.0 * dot(c2, c2);
    const double dg2 = dg * dg, den = dg2 - 0.5 * g * g2;
    const bool halley = den > 0.5 * dg2;  // Newton's where Halley's correction is large
    const double ds = halley ? -(g * dg) / den : -g / dg, sn = s + ds;
    const double off = sn - s0;
    if (!(off * off * s2_0 < r2)) return false;  // outside the window
    s = sn;
    // the step's error: the step itself, or Halley's estimate of what is left after it
    const double ads = std::abs(ds);
    double e = ads;
    if (halley) e = std::min(e, 4.0 * std::abs(0.25 * g2 * g2 - g3 * dg * (1.0 / 6.0)) / dg2 * ads * ads * ads);
    // e |C'| <= 1e-9 |q| + 1e-15: squared first (sufficient), then as written
    const double qq = dot(q, q), es2 = e * e * s2;
    if (es2 <= 1e-18 * qq || es2 <= 1e-30 || e * std::sqrt(s2) <= 1e-9 * std::sqrt(qq) + 1e-15) {
      const double speed = std::sqrt(s2);
      const double kappa = std::abs(cross(c1, c2)) / (s2 * speed);
      const Vec2 qn = m_.at(d0, s);
      const double d = std::sqrt(dot(qn, qn));
      if (!(kappa * (d + reach) <= 0.5)) return false;
      dist_ = d;
      kappa_ = kappa;
      u_out = wrap(m_.uc + s);
      last_u_ = u_out;
      last_s_ = s;
      pred_left_ = 0;
      return true;
    }
  }
  return false;
}

double FootTracker::find(Vec2 p, double guess, double reach) {
  if (tracking_ && !full_) {
    double u;
    if (model_on_ && model_track(p, guess, reach, u)) return u;
    if (track(p, guess, reach, u)) return u;
  }

  tracking_ = true;
  kappa_ = std::numeric_limits<double>::quiet_NaN();  // the window search does not vouch for the neighbourhood
  const double span = u1_ - u0_;
  double speed = norm(c_.eval(wrap(guess), 1).d1);
  double w = speed > 0.0 ? reach / speed : span;
  w = std::min(w, closed_ ? 0.5 * span : span);
  constexpr int K = 12;
  double lo = 0, hi = 0, best_u = guess, best = 0;
  for (int attempt = 0; attempt < 64; ++attempt) {
    lo = guess - w, hi = guess + w;
    if (!closed_) lo = std::max(lo, u0_), hi = std::min(hi, u1_);
    int b = 0;
    for (int i = 0; i <= K; ++i) {
      const double u = lo + (hi - lo) * i / K, d = d2(u, p);
      if (i == 0 || d < best) best = d, b = i, best_u = u;
    }
    if (b == 0 && (closed_ || lo > u0_)) {
      guess = lo;
      continue;
    }
    if (b == K && (closed_ || hi < u1_)) {
      guess = hi;
      continue;
    }
    const double h = (hi - lo) / K;
    lo = std::max(best_u - h, closed_ ? best_u - h : u0_);
    hi = std::min(best_u + h, closed_ ? best_u + h : u1_);
    break;
  }
  // Newton on the stationarity condition g(u) = (C(u) - p) . C'(u) = 0 from the best sample, kept inside the
  // bracket; where it does not settle quickly (a corner of the path, a point on its medial axis), golden section
  if (newton(p, lo, hi, best_u, best)) {
    dist_ = std::sqrt(best);
    return wrap(best_u);
  }
  double x1 = hi - kGolden * (hi - lo), x2 = lo + kGolden * (hi - lo), f1 = d2(x1, p), f2 = d2(x2, p);
  for (int it = 0; it < 40; ++it) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1, x1 = hi - kGolden * (hi - lo), f1 = d2(x1, p);
    } else {
      lo = x1, x1 = x2, f1 = f2, x2 = lo + kGolden * (hi - lo), f2 = d2(x2, p);
    }
  }
  const double u = f1 < f2 ? x1 : x2, d = std::min(f1, f2);
  if (d < best) best_u = u, best = d;
  dist_ = std::sqrt(best);
  return wrap(best_u);
}

bool FootTracker::newton(Vec2 p, double lo, double hi, double& u_io, double& d2_io) const {
  double u = u_io;
  for (int it = 0; it < 8; ++it) {
    const CurvePoint c = c_.eval(wrap(u), 2);
    const Vec2 q = c.p - p;
    const double g = dot(q, c.d1), dg = dot(c.d1, c.d1) + dot(q, c.d2);
    if (!(dg > 0.0)) return false;  // not a minimum nearby
    const double du = -g / dg, un = u + du;
    if (!(un > lo && un < hi)) return false;
    u = un;
    // converged once the step is far below the parameter's resolution of the distance (its effect on the
    // distance is second order in it)
    if (std::abs(du) * std::sqrt(dot(c.d1, c.d1)) <= 1e-9 * std::sqrt(dot(q, q)) + 1e-15) {
      const double dn = d2(u, p);
      if (!(dn <= d2_io * (1.0 + 1e-12) + 1e-30)) return false;  // another, worse minimum: search instead
      if (dn < d2_io) u_io = u, d2_io = dn;
      return true;
    }
  }
  return false;
}

DeviationMeter::DeviationMeter(const Curve& path)
    : c_(path), ft_(path), breaks_(path.breakpoints()), span_(path.u_end() - path.u_begin()), closed_(path.closed()) {}

void DeviationMeter::consider(double d, Vec2 p) {
  if (d > max_) {
    max_ = d;
    at_ = p;
  }
}

void DeviationMeter::start(Vec2 node, double reach) {
  max_ = 0.0;
  at_ = node;
  refined_ = middles_ = 0;
  u_ = ft_.find(node, c_.u_begin(), reach);
  d_node_ = ft_.distance();
  k_node_ = ft_.curvature();
  node_exact_ = true;
  node_ = node;
  bounded_ = 0;
  consider(d_node_, node);
}

void DeviationMeter::find_end(Vec2 q, double guess, double reach, double& u, double& d, double& k) {
  u = ft_.find(q, guess, reach);
  d = ft_.distance();
  k = ft_.curvature();
  consider(d, q);
}

DeviationMeter::Feet DeviationMeter::piece_rest(const StairPiece& p, double reach, Ends& e, double len) {
  const Vec2 pb = p.b;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // The middle and the search below judge by the ends' distances themselves: the ends' feet, where bounded, are
  // found, and the tests made again.
  if (!e.exact_a || !e.exact_b) {
    if (!e.exact_a) find_end(node_, e.u_a, reach, e.u_a, e.d_a, e.k_a);
    if (!e.exact_b) {
      find_end(pb, e.u_b, reach, e.u_b, e.d_b, e.k_b);
      e.exact_b = true;
    }
    if (ends_done(p, e, len)) {
      keep_end(e, pb);
      return {e.u_a, nan, e.u_b};
    }
  }
  keep_end(e, pb);
  ++middles_;
  const double u_a = e.u_a, d_a = e.d_a, u_b = e.u_b, d_b = e.d_b;

  const Vec2 pm = p.at(0.5);
  const double u_m = ft_.find(pm, u_b, reach);
  const double d_m = ft_.distance();
  consider(d_m, pm);
  const double bound = std::max({d_a, d_m, d_b}) + 0.25 * len;  // distance is 1-Lipschitz along the piece
  // the parabola through the three samples has its maximum inside the piece
  const double curv = 2.0 * d_m - d_a - d_b;
  const bool inside = curv > 0.0 && std::abs(d_b - d_a) < 2.0 * curv;
  if (bound > max_ && (inside || breaks_between(u_a, u_m) || breaks_between(u_m, u_b))) {
    // golden-section search for the largest distance on the piece (it is unimodal there: concave where it has a
    // kink, smooth otherwise)
    ++refined_;
    double lo = 0.0, hi = 1.0, u = u_m;
    auto dist = [&](double tau) {
      u = ft_.find(p.at(tau), u, reach);
      return ft_.distance();
    };
    double x1 = hi - kGolden * (hi - lo), x2 = lo + kGolden * (hi - lo), f1 = dist(x1), f2 = dist(x2);
    for (int it = 0; it < 30; ++it) {
      if (f1 > f2) {
        hi = x2, x2 = x1, f2 = f1, x1 = hi - kGolden * (hi - lo), f1 = dist(x1);
      } else {
        lo = x1, x1 = x2, f1 = f2, x2 = lo + kGolden * (hi - lo), f2 = dist(x2);
      }
    }
    const double tau = f1 > f2 ? x1 : x2;
    consider(std::max(f1, f2), p.at(tau));
  }
  return {u_a, u_m, u_b};
}

double DeviationMeter::middle_foot(const StairPiece& p, double reach) { return ft_.find(p.at(0.5), u_, reach); }

}  // namespace polarcam
