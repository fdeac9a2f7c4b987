#include "metrics/sector_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>


namespace polarcam::sweep {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kMinWidth = 1e-14;  // lambda: intervals narrower than this carry no area worth computing
constexpr int kMaxSplits = 64;       // crossings of two non-level strands located inside one sector

}  // namespace

double SectorSolver::lambda_at(uint32_t piece, double t, int64_t j) const {
  const PieceView& p = tr_.pieces[piece];
  return (p.g_a + (*p.G)(t) + fr_.shift) / fr_.width - static_cast<double>(j);
}

double SectorSolver::contour_t_at(const Strand& s, double l) const {
  if (l == s.l0) return s.t0;
  if (l == s.l1) return s.t1;
  const PieceView& p = tr_.pieces[s.piece];
  const double y = (static_cast<double>(s.j) + l) * fr_.width - fr_.shift - p.g_a;
  const double lo = std::min(s.t0, s.t1), hi = std::max(s.t0, s.t1);
  return cheb_solve(*p.G, y, lo, hi, (*p.G)(lo) - y, (*p.G)(hi) - y);
}

double SectorSolver::contour_t_at_height(uint32_t piece, double ta, double tb, double rho) const {
  const PieceView& p = tr_.pieces[piece];
  const double y = rho - p.h_a, lo = std::min(ta, tb), hi = std::max(ta, tb);
  return cheb_solve(*p.H, y, lo, hi, (*p.H)(lo) - y, (*p.H)(hi) - y);
}

double SectorSolver::height(const Strand& s, double l) const {
  switch (s.kind) {
    case Strand::level: return s.rho;
    case Strand::contour: {
      if (l == s.l0) return s.h0;
      if (l == s.l1) return s.h1;
      const PieceView& p = tr_.pieces[s.piece];
      return p.h_a + (*p.H)(contour_t_at(s, l));
    }
    case Strand::segment: {
      const double g = (static_cast<double>(s.j) + l) * fr_.width - fr_.shift;
      const Vec2 d = s.b - s.a;
      if (fr_.geo == Geometry::cartesian) return s.a.y + (g - s.a.x) / d.x * d.y;  // d.x != 0: it spans a strip
      const Vec2 u{std::cos(g), std::sin(g)};
      return cross(s.a, d) / cross(u, d);
    }
  }
  return 0.0;
}

double SectorSolver::area_integral(const Strand& s, double la, double lb) const {
  const double w = (lb - la) * fr_.width;
  const bool polar = fr_.geo == Geometry::polar;
  switch (s.kind) {
    case Strand::level: return polar ? 0.5 * s.rho * s.rho * w : s.rho * w;
    case Strand::contour: {
      const PieceView& p = tr_.pieces[s.piece];
      const LongCheb& A = areas_[s.piece];
      const double ta = contour_t_at(s, la), tb = contour_t_at(s, lb);
      return A(tb) - A(ta) + (polar ? 0.5 * p.h_a * p.h_a : p.h_a) * w;
    }
    case Strand::segment: {
      const double ha = height(s, la), hb = height(s, lb);
      if (!polar) return 0.5 * (ha + hb) * w;  // a trapezoid
      return 0.5 * ha * hb * std::sin(w);    // a triangle with its apex at the pole
    }
  }
  return 0.0;
}

void SectorSolver::crossings(const Strand& c, const Strand& lv, std::vector<double>& ev) const {
  const double lo = std::max(c.l0, lv.l0), hi = std::min(c.l1, lv.l1);
  if (!(hi > lo)) return;
  if (c.kind == Strand::contour) {
    const double hmin = std::min(c.h0, c.h1), hmax = std::max(c.h0, c.h1);
    if (!(lv.rho > hmin && lv.rho < hmax)) return;
    const double t = contour_t_at_height(c.piece, c.t0, c.t1, lv.rho);
    const double l = lambda_at(c.piece, t, c.j);
    if (l > lo && l < hi) ev.push_back(l);
  } else if (c.kind == Strand::segment) {
    const Vec2 d = c.b - c.a;
    if (fr_.geo == Geometry::cartesian) {
      if (d.y == 0.0) return;
      const double tau = (lv.rho - c.a.y) / d.y;
      if (!(tau > 0.0 && tau < 1.0)) return;
      const double l = (c.a.x + tau * d.x) / fr_.width - static_cast<double>(c.j);
      if (l > lo && l < hi) ev.push_back(l);
      return;
    }
    const double qa = dot(d, d), qb = 2.0 * dot(c.a, d), qc = dot(c.a, c.a) - lv.rho * lv.rho;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (!(qa > 0.0) || disc < 0.0) return;
    const double sq = std::sqrt(disc), q = -0.5 * (qb + std::copysign(sq, qb));
    for (double tau : {q / qa, q != 0.0 ? qc / q : -1.0}) {
      if (!(tau > 0.0 && tau < 1.0)) continue;
      const Vec2 p = c.a + tau * d;
      const double ref = (static_cast<double>(c.j) + 0.5) * fr_.width - fr_.shift;
      const double phi = ref + std::remainder(std::atan2(p.y, p.x) - ref, kTwoPi);
      const double l = (phi + fr_.shift) / fr_.width - static_cast<double>(c.j);
      if (l > lo && l < hi) ev.push_back(l);
    }
  }
}

double SectorSolver::area(const std::vector<Strand>& strands) const {
  std::vector<double> ev{0.0, 1.0};
  for (const Strand& s : strands) {
    ev.push_back(s.l0);
    ev.push_back(s.l1);
  }
  for (const Strand& a : strands)
    if (a.kind == Strand::level)
      for (const Strand& c : strands)
        if (c.kind != Strand::level) crossings(c, a, ev);
  for (double& e : ev) e = std::clamp(e, 0.0, 1.0);
  std::sort(ev.begin(), ev.end());
  ev.erase(std::unique(ev.begin(), ev.end()), ev.end());

  struct Interval {
    double a, b;
    int depth;
  };
  std::vector<Interval> work;
  for (size_t i = ev.size(); i-- > 1;) work.push_back({ev[i - 1], ev[i], 0});

  double total = 0.0;
  std::vector<size_t> act, order;
  std::vector<double> h0, hm, h1, F;
  while (!work.empty()) {
    const Interval iv = work.back();
    work.pop_back();
    if (!(iv.b - iv.a > kMinWidth)) continue;
    act.clear();
    for (size_t i = 0; i < strands.size(); ++i)
      if (strands[i].l0 <= iv.a && strands[i].l1 >= iv.b) act.push_back(i);
    if (act.empty()) continue;
    const double mid = 0.5 * (iv.a + iv.b);
    const size_t k = act.size();
    h0.assign(k, 0.0);
    hm.assign(k, 0.0);
    h1.assign(k, 0.0);
    for (size_t i = 0; i < k; ++i) {
      const Strand& s = strands[act[i]];
      hm[i] = height(s, mid);
      if (s.kind != Strand::level) {
        h0[i] = height(s, iv.a);
        h1[i] = height(s, iv.b);
      } else {
        h0[i] = h1[i] = s.rho;
      }
    }
    // two curved or slanted strands may cross inside the interval: find the crossing and split there
    bool split = false;
    for (size_t x = 0; x < k && !split; ++x)
      for (size_t y = x + 1; y < k && !split; ++y) {
        const Strand& sx = strands[act[x]];
        const Strand& sy = strands[act[y]];
        if (sx.kind == Strand::level && sy.kind == Strand::level) continue;
        const double d0 = h0[x] - h0[y], dm = hm[x] - hm[y], d1 = h1[x] - h1[y];
        double lo, hi, dlo;
        if ((dm > 0 && d1 < 0) || (dm < 0 && d1 > 0)) {
          lo = mid, hi = iv.b, dlo = dm;
        } else if ((d0 > 0 && dm < 0) || (d0 < 0 && dm > 0)) {
          lo = iv.a, hi = mid, dlo = d0;
        } else {
          continue;
        }
        if (iv.depth >= kMaxSplits) continue;
        for (int it = 0; it < 200 && hi - lo > kMinWidth; ++it) {
          const double m = 0.5 * (lo + hi), dd = height(sx, m) - height(sy, m);
          if (dd == 0.0) {
            lo = hi = m;
            break;
          }
          if ((dd > 0) == (dlo > 0))
            lo = m;
          else
            hi = m;
        }
        const double c = 0.5 * (lo + hi);
        if (c > iv.a && c < iv.b) {
          work.push_back({iv.a, c, iv.depth + 1});
          work.push_back({c, iv.b, iv.depth + 1});
          split = true;
        }
      }
    if (split) continue;

    order.resize(k);
    std::iota(order.begin(), order.end(), size_t{0});
    std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return hm[x] < hm[y]; });
    F.assign(k, 0.0);
    int wsum = 0;
    for (size_t i = 0; i < k; ++i) {
      F[i] = area_integral(strands[act[i]], iv.a, iv.b);
      wsum += strands[act[i]].sigma;
    }
    // from below upwards: below the lowest strand the winding number is the sum of all orientations (0 in the
    // Cartesian geometry, where nothing lies below; at the pole in the polar one)
    double prevF = 0.0;
    int w = wsum;
    size_t i0 = 0;
    if (fr_.geo == Geometry::cartesian) {
      prevF = F[order[0]];
      w -= strands[act[order[0]]].sigma;
      i0 = 1;
    }
    for (size_t i = i0; i < k; ++i) {
      const size_t s = order[i];
      total += std::abs(w) * (F[s] - prevF);
      prevF = F[s];
      w -= strands[act[s]].sigma;
    }
  }
  return total;
}

}  // namespace polarcam::sweep
