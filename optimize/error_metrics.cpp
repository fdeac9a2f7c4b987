#include "optimize/error_metrics.hpp"

#include <algorithm>
#include <cmath>

namespace polarcam {
namespace {

// Foot points of a moving point on a curve: the parameter of the nearest point of the curve, searched near the
// previous one. The window (a few grid cells of path either side) is sampled, moved on while the nearest sample
// is at its edge, and the best sample's neighbourhood refined by golden-section search.
class FootTracker {
 public:
  explicit FootTracker(const Curve& c) : c_(c), u0_(c.u_begin()), u1_(c.u_end()), closed_(c.closed()) {}

  double find(Vec2 p, double guess, double reach) {
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
    const double g = 0.6180339887498949;
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = d2(x1, p), f2 = d2(x2, p);
    for (int it = 0; it < 40; ++it) {
      if (f1 < f2) {
        hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = d2(x1, p);
      } else {
        lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = d2(x2, p);
      }
    }
    const double u = f1 < f2 ? x1 : x2, d = std::min(f1, f2);
    if (d < best) best_u = u, best = d;
    dist_ = std::sqrt(best);
    return wrap(best_u);
  }
  double distance() const { return dist_; }

 private:
  double wrap(double u) const {
    if (!closed_) return std::clamp(u, u0_, u1_);
    const double span = u1_ - u0_;
    double v = std::fmod(u - u0_, span);
    if (v < 0) v += span;
    return u0_ + v;
  }
  double d2(double u, Vec2 p) const {
    const Vec2 q = c_.eval(wrap(u), 0).p - p;
    return dot(q, q);
  }
  const Curve& c_;
  double u0_, u1_;
  bool closed_;
  double dist_ = 0.0;
};

}  // namespace

void ErrorMeters::reset(const Curve& path, const PolarTrack& track, const Grid& grid, int segments) {
  path_ = &path;
  track_ = &track;
  grid_ = grid;
  segments_ = std::max(1, segments);
  steps_.clear();
  area_.reset(track, grid);
}

ErrorMetrics ErrorMeters::finish(int64_t n0, int64_t m0) {
  ErrorMetrics out;
  out.area = area_.finish(n0, m0);  // checks that the staircase follows the path
  const double dr = grid_.dr, dth = grid_.dtheta;
  const Curve& c = *path_;
  const double u0 = c.u_begin(), u1 = c.u_end();
  auto at = [&](double n, double m) {
    const double rho = n * dr, phi = m * dth;
    return Vec2{rho * std::cos(phi), rho * std::sin(phi)};
  };
  auto reach = [&](double n) { return 3.0 * std::max(dr, n * dr * dth) + 1e-12; };

  const int ns = segments_;
  std::vector<long long> nr(static_cast<size_t>(ns), 0), nt(static_cast<size_t>(ns), 0);
  auto segment_of = [&](double u) {
    const int i = static_cast<int>(std::floor((u - u0) / (u1 - u0) * ns));
    return std::clamp(i, 0, ns - 1);
  };

  FootTracker ft(c);
  double n = static_cast<double>(n0), m = static_cast<double>(m0);
  double u = ft.find(at(n, m), u0, reach(n));
  auto consider = [&](Vec2 p) {
    if (ft.distance() > out.deviation_max_m) {
      out.deviation_max_m = ft.distance();
      out.deviation_at = p;
    }
  };
  consider(at(n, m));
  for (uint8_t s : steps_) {
    const int axis = s & 1, dir = (s & 2) ? 1 : -1;
    // the middle of the step's segment or arc
    const double mn = axis == kAxisRadial ? n + 0.5 * dir : n, mm = axis == kAxisRadial ? m : m + 0.5 * dir;
    const Vec2 pm = at(mn, mm);
    u = ft.find(pm, u, reach(mn));
    consider(pm);
    (axis == kAxisRadial ? nr : nt)[static_cast<size_t>(segment_of(u))] += 1;
    (axis == kAxisRadial ? n : m) += dir;
    const Vec2 pn = at(n, m);
    u = ft.find(pn, u, reach(n));
    consider(pn);
  }

  const double rmax = track_->r_max().value, K = dr / dth;
  out.deviation_eq41_m = rmax <= K ? dr : rmax * dth;
  out.segments = ns;
  const std::vector<Vec2> pts = segment_points(c, ns);
  out.f_counts = f1_counts(pts, nr, nt, dr, dth);
  out.f_chords = f1_chords(pts, dr, dth);
  steps_.clear();
  return out;
}

}  // namespace polarcam
