#include "cam/thr_export.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "cam/error.hpp"

namespace polarcam {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTurn = 2.0 * kPi;
constexpr int kScan = 64;                  // points per piece scanned for pole crossings
constexpr int kSideSamples = 32;               // sample intervals of each side of the distance measure
constexpr double kAccept = 0.98;           // a segment is kept at this fraction of the tolerance
constexpr double kMaxTurn = kPi / 2;       // largest arm turn of one segment
constexpr double kUnwrapStep = kPi / 4;    // largest angle between neighbouring unwrapping samples
constexpr int kMaxBisection = 48;              // bisection depth (a 2^-48 part of a piece is kept as it is)

std::string at_u(double u) {
  std::ostringstream os;
  os.precision(10);
  os << "the path has no finite point at parameter u = " << u;
  return os.str();
}

Vec2 point(const Curve& c, double u) {
  const Vec2 p = c.eval(u, 0).p;
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw InputError(at_u(u));
  return p;
}

double angle(Vec2 p) { return std::atan2(p.y, p.x); }

// The value of `a` + 2 pi k nearest to `ref`; a half turn either way (within 1e-6 rad) is taken counter-clockwise.
double unwrap(double a, double ref) {
  double d = std::remainder(a - ref, kTurn);  // in [-pi, pi]
  if (std::abs(d) > kPi - 1e-6) d = kPi;
  return ref + d;
}

// A segment linear in theta and rho, f in [0, 1], with its first two derivatives in f.
struct Spiral {
  ThetaRho a, b;
  CurvePoint eval(double f) const {
    const double dth = b.theta - a.theta, drho = b.rho - a.rho;
    const double th = a.theta + dth * f, rho = a.rho + drho * f;
    const Vec2 e{std::cos(th), std::sin(th)}, n{-e.y, e.x};
    CurvePoint p;
    p.p = rho * e;
    p.d1 = drho * e + rho * dth * n;
    p.d2 = 2.0 * drho * dth * n - rho * dth * dth * e;
    return p;
  }
};

// The distance from p to the nearest point of f on [lo, hi], from t (at distance d0): a safeguarded Newton
// iteration on g(t) = (f(t) - p) . f'(t), bisecting the bracket when a step leaves it. Every distance taken is
// one to an actual point of f, so the result is never below the true distance.
template <class F>
double nearest_distance(const F& f, Vec2 p, double lo, double hi, double t, double d0) {
  double best = d0;
  const double span = hi - lo;
  for (int it = 0; it < 16; ++it) {
    const CurvePoint c = f(t);
    const Vec2 d = c.p - p;
    best = std::min(best, norm(d));
    const double g = dot(d, c.d1);
    const double h = dot(c.d1, c.d1) + dot(d, c.d2);
    if (g > 0.0) {
      hi = t;
    } else if (g < 0.0) {
      lo = t;
    } else {
      break;
    }
    double next = h > 0.0 ? t - g / h : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - t) <= 1e-14 * span) break;
    t = next;
  }
  return best;
}

// The largest distance from the points `from` to the path `f` sampled as `to` at parameters `tt`, raised into
// `worst`; false as soon as it exceeds `limit`.
template <class F>
bool one_way(const std::array<Vec2, kSideSamples + 1>& from, const std::array<Vec2, kSideSamples + 1>& to,
             const std::array<double, kSideSamples + 1>& tt, const F& f, double limit, double& worst) {
  for (int k = 0; k <= kSideSamples; ++k) {
    int j = 0;
    double d0 = norm(from[k] - to[0]);
    for (int i = 1; i <= kSideSamples; ++i) {
      const double d = norm(from[k] - to[i]);
      if (d < d0) d0 = d, j = i;
    }
    if (d0 <= worst) continue;  // the refined distance is at most d0
    const double d = nearest_distance(f, from[k], tt[std::max(j - 1, 0)], tt[std::min(j + 1, kSideSamples)], tt[j], d0);
    worst = std::max(worst, d);
    if (worst > limit) return false;
  }
  return true;
}

// The distance between the spiral segment s and the curve piece [ua, ub], measured both ways (see the header);
// a value above `limit` as soon as it is known to exceed it.
double piece_distance(const Curve& c, double ua, double ub, const Spiral& s, double limit) {
  std::array<Vec2, kSideSamples + 1> pc, ps;
  std::array<double, kSideSamples + 1> uc, fs;
  for (int k = 0; k <= kSideSamples; ++k) {
    uc[k] = k == kSideSamples ? ub : ua + (ub - ua) * k / kSideSamples;
    fs[k] = static_cast<double>(k) / kSideSamples;
    pc[k] = point(c, uc[k]);
    ps[k] = s.eval(fs[k]).p;
  }
  double worst = 0.0;
  if (!one_way(pc, ps, fs, [&](double f) { return s.eval(f); }, limit, worst)) return worst;
  one_way(ps, pc, uc, [&](double u) { return c.eval(u, 2); }, limit, worst);
  return worst;
}

// Parameters strictly inside (ua, ub) where the path runs through the pole (within eps).
std::vector<double> pole_crossings(const Curve& c, double ua, double ub, double eps) {
  std::array<double, kScan + 1> u, rho;
  std::array<Vec2, kScan + 1> p;
  for (int k = 0; k <= kScan; ++k) {
    u[k] = k == kScan ? ub : ua + (ub - ua) * k / kScan;
    p[k] = point(c, u[k]);
    rho[k] = norm(p[k]);
  }
  std::vector<double> out;
  const double margin = 1e-9 * (ub - ua);
  for (int k = 1; k < kScan; ++k) {
    if (!(rho[k] <= rho[k - 1] && rho[k] <= rho[k + 1])) continue;
    // the path between the neighbouring samples cannot come closer to the pole than this
    const double reach = 2.0 * std::max(norm(p[k] - p[k - 1]), norm(p[k + 1] - p[k]));
    if (rho[k] > eps + reach) continue;
    // golden section on |P(u)| over the two sample intervals
    constexpr double g = 0.6180339887498949;
    double a = u[k - 1], b = u[k + 1];
    double x1 = b - g * (b - a), x2 = a + g * (b - a);
    double f1 = norm(point(c, x1)), f2 = norm(point(c, x2));
    for (int it = 0; it < 200 && b - a > 1e-15 * (ub - ua); ++it) {
      if (f1 <= f2) {
        b = x2, x2 = x1, f2 = f1;
        x1 = b - g * (b - a), f1 = norm(point(c, x1));
      } else {
        a = x1, x1 = x2, f1 = f2;
        x2 = a + g * (b - a), f2 = norm(point(c, x2));
      }
    }
    const double um = f1 <= f2 ? x1 : x2;
    if (std::min(f1, f2) <= eps && um > ua + margin && um < ub - margin &&
        (out.empty() || um > out.back() + margin))
      out.push_back(um);
  }
  return out;
}

// The direction along which the path leaves (side = +1) or reaches (side = -1) the pole at u, the piece being
// [ua, ub]: from the first derivative just inside the piece, from the second at a cusp, else from a nearby point.
double pole_angle(const Curve& c, double u, int side, double ua, double ub) {
  const double h = 1e-9 * (ub - ua);
  const double ue = side > 0 ? std::min(u + h, ub) : std::max(u - h, ua);
  const CurvePoint cp = c.eval(ue, 2);
  const double chord = norm(point(c, ub) - point(c, ua));
  const double scale = std::max(chord, 1e-300) / (ub - ua);  // a typical |P'|
  const Vec2 d1 = cp.d1 + (u - ue) * cp.d2;                  // P'(u) from inside the piece
  if (norm(d1) > 1e-6 * scale) return angle(side * d1);
  if (norm(cp.d2) > 1e-6 * scale / (ub - ua)) return angle(cp.d2);
  const double un = side > 0 ? u + 1e-4 * (ub - ua) : u - 1e-4 * (ub - ua);
  return angle(point(c, un));
}

struct Sample {
  double u, theta;
};

class PieceWriter {
 public:
  PieceWriter(const Curve& c, double tol) : c_(c), tol_(tol) {}

  // Appends the vertices of the piece [ua, ub] after `out.back()` (its first vertex, already in `out`).
  void run(double ua, double ub, bool pole_b, std::vector<ThetaRho>& out) {
    const ThetaRho va = out.back();
    // unwrapping samples: the start, 31 inside, the end
    samples_.clear();
    samples_.push_back({ua, va.theta});
    for (int k = 1; k <= kSideSamples; ++k) {
      const double u = k == kSideSamples ? ub : ua + (ub - ua) * k / kSideSamples;
      const double raw = (k == kSideSamples && pole_b) ? pole_angle(c_, ub, -1, ua, ub) : angle(point(c_, u));
      add_sample(u, raw, 0);
    }
    ThetaRho vb{samples_.back().theta, pole_b ? 0.0 : norm(point(c_, ub))};
    bisect(ua, va, ub, vb, 0, out);
  }

 private:
  void add_sample(double u1, double raw1, int depth) {
    const Sample last = samples_.back();
    const double t1 = unwrap(raw1, last.theta);
    if (std::abs(t1 - last.theta) > kUnwrapStep && depth < 40) {
      const double um = 0.5 * (last.u + u1);
      add_sample(um, angle(point(c_, um)), depth + 1);
      add_sample(u1, raw1, depth + 1);
      return;
    }
    samples_.push_back({u1, t1});
  }

  ThetaRho vertex(double u) const {
    const Vec2 p = point(c_, u);
    auto it = std::lower_bound(samples_.begin(), samples_.end(), u, [](const Sample& s, double x) { return s.u < x; });
    if (it == samples_.end()) --it;
    if (it != samples_.begin() && u - std::prev(it)->u < it->u - u) --it;
    return {unwrap(angle(p), it->theta), norm(p)};
  }

  void bisect(double ua, const ThetaRho& va, double ub, const ThetaRho& vb, int depth, std::vector<ThetaRho>& out) {
    const double limit = kAccept * tol_;
    bool keep = std::abs(vb.theta - va.theta) <= kMaxTurn * (1.0 + 1e-12) &&
                piece_distance(c_, ua, ub, Spiral{va, vb}, limit) <= limit;
    if (keep || depth >= kMaxBisection) {
      if (vb.theta != out.back().theta || vb.rho != out.back().rho) out.push_back(vb);
      return;
    }
    const double um = 0.5 * (ua + ub);
    const ThetaRho vm = vertex(um);
    bisect(ua, va, um, vm, depth + 1, out);
    bisect(um, vm, ub, vb, depth + 1, out);
  }

  const Curve& c_;
  double tol_;
  std::vector<Sample> samples_;
};

}  // namespace

std::vector<ThetaRho> to_theta_rho(const Curve& path, double tolerance_m) {
  if (const ThetaRhoPath* tr = as_theta_rho_path(path)) return tr->vertices();
  if (!(tolerance_m > 0.0) || !std::isfinite(tolerance_m)) throw InputError("the tolerance must be a positive length");
  const double eps = 1e-3 * tolerance_m;  // closer to the pole than this is through it

  // pieces between breakpoints and pole crossings, with whether each end is at the pole
  std::vector<double> cuts{path.u_begin()};
  for (double b : path.breakpoints())
    if (b > cuts.back()) cuts.push_back(b);
  if (path.u_end() > cuts.back()) cuts.push_back(path.u_end());
  std::vector<double> ends{cuts.front()};
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    for (double u : pole_crossings(path, cuts[i], cuts[i + 1], eps)) ends.push_back(u);
    ends.push_back(cuts[i + 1]);
  }
  if (ends.size() < 2) throw InputError("the path has no length");
  std::vector<bool> at_pole(ends.size());
  for (size_t i = 0; i < ends.size(); ++i) at_pole[i] = norm(point(path, ends[i])) <= eps;

  std::vector<ThetaRho> out;
  PieceWriter writer(path, tolerance_m);
  for (size_t i = 0; i + 1 < ends.size(); ++i) {
    const double ua = ends[i], ub = ends[i + 1];
    // the piece's first vertex: the last one, or at the pole the angle the path leaves along
    if (at_pole[i]) {
      const double raw = pole_angle(path, ua, +1, ua, ub);
      const ThetaRho v{out.empty() ? raw : unwrap(raw, out.back().theta), 0.0};
      if (out.empty() || v.theta != out.back().theta || out.back().rho != 0.0) out.push_back(v);
    } else if (out.empty()) {
      const Vec2 p = point(path, ua);
      out.push_back({angle(p), norm(p)});
    }
    writer.run(ua, ub, at_pole[i + 1], out);
  }
  if (out.size() < 2) throw InputError("the path has no length");
  return out;
}

}  // namespace polarcam
