#include "optimize/sector_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace polarcam::sweep {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kMinWidth = 1e-14;  // lambda: intervals narrower than this carry no area worth computing
constexpr int kMaxSplits = 64;       // crossings of two non-arc strands located inside one sector

}  // namespace

double SectorSolver::lambda_at(uint32_t piece, double t, int64_t j) const {
  const TrackPiece& p = tr_.pieces()[piece];
  return (p.th_a + p.Th(t) + fr_.shift) / fr_.dtheta - static_cast<double>(j);
}

double SectorSolver::contour_t_at(const Strand& s, double l) const {
  if (l == s.l0) return s.t0;
  if (l == s.l1) return s.t1;
  const TrackPiece& p = tr_.pieces()[s.piece];
  const double y = (static_cast<double>(s.j) + l) * fr_.dtheta - fr_.shift - p.th_a;
  const double lo = std::min(s.t0, s.t1), hi = std::max(s.t0, s.t1);
  return cheb_solve(p.Th, y, lo, hi, p.Th(lo) - y, p.Th(hi) - y);
}

double SectorSolver::contour_t_at_radius(uint32_t piece, double ta, double tb, double rho) const {
  const TrackPiece& p = tr_.pieces()[piece];
  const double y = rho - p.r_a, lo = std::min(ta, tb), hi = std::max(ta, tb);
  return cheb_solve(p.R, y, lo, hi, p.R(lo) - y, p.R(hi) - y);
}

double SectorSolver::radius(const Strand& s, double l) const {
  switch (s.kind) {
    case Strand::arc: return s.rho;
    case Strand::contour: {
      if (l == s.l0) return s.r0;
      if (l == s.l1) return s.r1;
      const TrackPiece& p = tr_.pieces()[s.piece];
      return p.r_a + p.R(contour_t_at(s, l));
    }
    case Strand::segment: {
      const double phi = (static_cast<double>(s.j) + l) * fr_.dtheta - fr_.shift;
      const Vec2 u{std::cos(phi), std::sin(phi)}, d = s.b - s.a;
      return cross(s.a, d) / cross(u, d);
    }
  }
  return 0.0;
}

double SectorSolver::half_r2_integral(const Strand& s, double la, double lb) const {
  switch (s.kind) {
    case Strand::arc: return 0.5 * s.rho * s.rho * (lb - la) * fr_.dtheta;
    case Strand::contour: {
      const TrackPiece& p = tr_.pieces()[s.piece];
      const LongCheb& A = areas_[s.piece];
      const double ta = contour_t_at(s, la), tb = contour_t_at(s, lb);
      return A(tb) - A(ta) + 0.5 * p.r_a * p.r_a * (lb - la) * fr_.dtheta;
    }
    case Strand::segment: {
      const double pa = (static_cast<double>(s.j) + la) * fr_.dtheta - fr_.shift;
      const double pb = (static_cast<double>(s.j) + lb) * fr_.dtheta - fr_.shift;
      const double ra = radius(s, la), rb = radius(s, lb);
      return 0.5 * ra * rb * std::sin(pb - pa);
    }
  }
  return 0.0;
}

void SectorSolver::crossings(const Strand& c, const Strand& arc, std::vector<double>& ev) const {
  const double lo = std::max(c.l0, arc.l0), hi = std::min(c.l1, arc.l1);
  if (!(hi > lo)) return;
  if (c.kind == Strand::contour) {
    const double rmin = std::min(c.r0, c.r1), rmax = std::max(c.r0, c.r1);
    if (!(arc.rho > rmin && arc.rho < rmax)) return;
    const double t = contour_t_at_radius(c.piece, c.t0, c.t1, arc.rho);
    const double l = lambda_at(c.piece, t, c.j);
    if (l > lo && l < hi) ev.push_back(l);
  } else if (c.kind == Strand::segment) {
    const Vec2 d = c.b - c.a;
    const double qa = dot(d, d), qb = 2.0 * dot(c.a, d), qc = dot(c.a, c.a) - arc.rho * arc.rho;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (!(qa > 0.0) || disc < 0.0) return;
    const double sq = std::sqrt(disc), q = -0.5 * (qb + std::copysign(sq, qb));
    for (double tau : {q / qa, q != 0.0 ? qc / q : -1.0}) {
      if (!(tau > 0.0 && tau < 1.0)) continue;
      const Vec2 p = c.a + tau * d;
      const double ref = (static_cast<double>(c.j) + 0.5) * fr_.dtheta - fr_.shift;
      const double phi = ref + std::remainder(std::atan2(p.y, p.x) - ref, kTwoPi);
      const double l = (phi + fr_.shift) / fr_.dtheta - static_cast<double>(c.j);
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
    if (a.kind == Strand::arc)
      for (const Strand& c : strands)
        if (c.kind != Strand::arc) crossings(c, a, ev);
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
  std::vector<double> r0, rm, r1, F;
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
    r0.assign(k, 0.0);
    rm.assign(k, 0.0);
    r1.assign(k, 0.0);
    for (size_t i = 0; i < k; ++i) {
      const Strand& s = strands[act[i]];
      rm[i] = radius(s, mid);
      if (s.kind != Strand::arc) {
        r0[i] = radius(s, iv.a);
        r1[i] = radius(s, iv.b);
      } else {
        r0[i] = r1[i] = s.rho;
      }
    }
    // two curved or slanted strands may cross inside the interval: find the crossing and split there
    bool split = false;
    for (size_t x = 0; x < k && !split; ++x)
      for (size_t y = x + 1; y < k && !split; ++y) {
        const Strand& sx = strands[act[x]];
        const Strand& sy = strands[act[y]];
        if (sx.kind == Strand::arc && sy.kind == Strand::arc) continue;
        const double d0 = r0[x] - r0[y], dm = rm[x] - rm[y], d1 = r1[x] - r1[y];
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
          const double m = 0.5 * (lo + hi), dd = radius(sx, m) - radius(sy, m);
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
    std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return rm[x] < rm[y]; });
    F.assign(k, 0.0);
    int wsum = 0;
    for (size_t i = 0; i < k; ++i) {
      F[i] = half_r2_integral(strands[act[i]], iv.a, iv.b);
      wsum += strands[act[i]].sigma;
    }
    // from the pole outwards: below the lowest strand the winding number is the sum of all orientations
    double prevF = 0.0;
    int w = wsum;
    for (size_t i = 0; i < k; ++i) {
      const size_t s = order[i];
      total += std::abs(w) * (F[s] - prevF);
      prevF = F[s];
      w -= strands[act[s]].sigma;
    }
  }
  return total;
}

}  // namespace polarcam::sweep
