#include "optimize/area_error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "cam/error.hpp"

namespace polarcam {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// f, f', f'' at t (Clenshaw with its derivatives)
inline void eval3(const Cheb& c, double t, double& f, double& d1, double& d2) {
  double b1 = 0, b2 = 0, e1 = 0, e2 = 0, h1 = 0, h2 = 0;
  const double tt = 2.0 * t;
  for (int k = c.deg; k >= 1; --k) {
    const double b0 = (c.c[k] - b2) + tt * b1, e0 = (2.0 * b1 - e2) + tt * e1, h0 = (4.0 * e1 - h2) + tt * h1;
    b2 = b1, b1 = b0, e2 = e1, e1 = e0, h2 = h1, h1 = h0;
  }
  f = (c.c[0] - b2) + t * b1;
  d1 = (b1 - e2) + t * e1;
  d2 = (2.0 * e1 - h2) + t * h1;
}

// R(t) and Astar(t) in one pass. Each series is split into its even and odd parts, T_2m(t) = T_m(y) and
// T_2m+1(t) = t V_m(y) with y = 2 t^2 - 1 (V: Chebyshev polynomials of the third kind, same recurrence,
// V_0 = 1, V_1 = 2y - 1), so four independent Clenshaw recurrences of half the length run side by side: the
// evaluation is bound by the length of the longest chain, which this halves.
inline void eval_rA(const Cheb& R, const LongCheb& A, double t, double& r, double& a) {
  const double y = 2.0 * t * t - 1.0, yy = 2.0 * y;
  double re1 = 0, re2 = 0, ro1 = 0, ro2 = 0, ae1 = 0, ae2 = 0, ao1 = 0, ao2 = 0;
  const int top = std::max(A.deg, R.deg) / 2 + 1;
  for (int m = top; m >= 1; --m) {
    const int ke = 2 * m, ko = 2 * m + 1;
    const double rce = ke <= R.deg ? R.c[ke] : 0.0, rco = ko <= R.deg ? R.c[ko] : 0.0;
    const double ace = ke <= A.deg ? A.c[ke] : 0.0, aco = ko <= A.deg ? A.c[ko] : 0.0;
    const double re0 = (rce - re2) + yy * re1, ro0 = (rco - ro2) + yy * ro1;
    const double ae0 = (ace - ae2) + yy * ae1, ao0 = (aco - ao2) + yy * ao1;
    re2 = re1, re1 = re0, ro2 = ro1, ro1 = ro0, ae2 = ae1, ae1 = ae0, ao2 = ao1, ao1 = ao0;
  }
  // even: c_0 + y b_1 - b_2; odd: t (b_0 - b_1) with b_0 = c_1 + 2y b_1 - b_2
  const double r_even = (R.c[0] - re2) + y * re1, r_odd = t * (((R.deg >= 1 ? R.c[1] : 0.0) - ro2) + (yy - 1.0) * ro1);
  const double a_even = (A.c[0] - ae2) + y * ae1, a_odd = t * (((A.deg >= 1 ? A.c[1] : 0.0) - ao2) + (yy - 1.0) * ao1);
  r = r_even + r_odd;
  a = a_even + a_odd;
}

// Th(t) and Astar(t) in one pass.
inline void eval_thA(const Cheb& Th, const LongCheb& A, double t, double& th, double& a) { eval_rA(Th, A, t, th, a); }

// Where r(t) = y on a part of a piece where r is monotone and y lies strictly between r(ta) - r_a and r(tb) - r_a
// (ya, yb). The area split there is in error by r |dr/dphi| dphi^2 for a crossing misplaced by dphi, so the crossing
// need not be found to rounding: Newton from the interpolated guess stops once the error left after its step,
// |R''/(2 R')| dt^2, is below 1e-12 (t on [-1, 1]; far inside the rounding of the area).
double radius_crossing(const Cheb& R, double y, double ta, double tb, double ya, double yb) {
  double lo = std::min(ta, tb), hi = std::max(ta, tb);
  const double chord = (yb - ya) / (tb - ta);
  double t = ta + (y - ya) / chord;
  if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
  const bool up = chord > 0;  // R - y increases with t
  for (int it = 0; it < 100; ++it) {
    double v, d, d2;
    eval3(R, t, v, d, d2);
    v -= y;
    if (v == 0.0) return t;
    if ((v > 0) == up)
      hi = t;
    else
      lo = t;
    double tn = d != 0.0 ? t - v / d : 0.5 * (lo + hi);
    if (!(tn > lo && tn < hi)) {
      t = 0.5 * (lo + hi);
      continue;
    }
    const double dt = tn - t;
    if (std::abs(d2) * dt * dt <= 2e-12 * std::abs(d) || hi - lo <= 1e-15) return tn;
    t = tn;
  }
  return t;
}

// Root of f(t) = y in [lo, hi] where f - y changes sign (flo = f(lo) - y), Newton from `guess` safeguarded by
// bisection. The last Newton step is taken without another evaluation once its own error f'' dt^2 / (2 f') is
// below 1e-15 (t is on [-1, 1]).
double solve_level(const Cheb& f, double y, double lo, double hi, double flo, double guess) {
  if (flo == 0.0) return lo;
  double t = (guess > lo && guess < hi) ? guess : 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    double v, d1, d2;
    eval3(f, t, v, d1, d2);
    v -= y;
    if (v == 0.0) return t;
    if ((v < 0) == (flo < 0))
      lo = t;
    else
      hi = t;
    double tn = 0.5 * (lo + hi);
    if (d1 != 0.0) {
      const double dt = -v / d1;
      if (t + dt > lo && t + dt < hi) {
        tn = t + dt;
        if (std::abs(dt) <= 1e-4 && std::abs(d2 * dt * dt) <= 2e-15 * std::abs(d1)) return tn;
      }
    }
    if (hi - lo <= 4e-16) return tn;
    t = tn;
  }
  return t;
}

std::string num(double v, int prec = 6) {
  std::ostringstream os;
  os.precision(prec);
  os << v;
  return os.str();
}

struct Neumaier {
  double s = 0.0, c = 0.0;
  void add(double x) {
    const double t = s + x;
    c += std::abs(s) >= std::abs(x) ? (s - t) + x : (x - t) + s;
    s = t;
  }
  double value() const { return s + c; }
};

}  // namespace

void PolarAreaMeter::reset(const PolarTrack& track, const Grid& grid) {
  track_ = &track;
  grid_ = grid;
  sector_area_series(track, areas_);
  arcs_.clear();
  n_ = m_ = 0;
  nr_ = 0;
}

uint32_t PolarAreaMeter::key(int64_t j) const {
  int64_t k = j - j_lo_;
  if (wrap_) {
    // j_lo_ maps to key_lo_; a few subtractions are cheaper than a 64-bit division
    const int64_t N = grid_.steps_per_rev;
    k += key_lo_;
    if (k >= 4 * N) k %= N;
    while (k >= N) k -= N;
  }
  return static_cast<uint32_t>(k);
}

void PolarAreaMeter::close_visit() {
  if (open_ < 0) return;
  Visit& v = visits_[static_cast<size_t>(open_)];
  const Sub& a = subs_[v.first];
  const Sub& b = subs_[v.first + v.count - 1];
  v.full = v.sigma != 0 && ((a.l0 == 0.0 && b.l1 == 1.0) || (a.l0 == 1.0 && b.l1 == 0.0));
  const uint32_t k = key(v.j);
  v.next = visit_head_[k];
  visit_head_[k] = open_;
  open_ = -1;
}

void PolarAreaMeter::add_sub(const Sub& s, int64_t j) {
  const int8_t sg = s.l1 > s.l0 ? 1 : -1;
  const double lo = s.r0 < s.r1 ? s.r0 : s.r1, hi = s.r0 < s.r1 ? s.r1 : s.r0;
  if (open_ >= 0) {
    Visit& v = visits_[static_cast<size_t>(open_)];
    if (v.j == j) {
      if (v.sigma != sg) v.sigma = 0;
      ++v.count;
      if (lo < v.rmin) v.rmin = lo;
      if (hi > v.rmax) v.rmax = hi;
      subs_.push_back(s);
      return;
    }
    close_visit();
  }
  open_ = static_cast<int>(visits_.size());
  visits_.push_back(Visit{j, static_cast<uint32_t>(subs_.size()), 1, -1, sg, false, lo, hi});
  subs_.push_back(s);
}

void PolarAreaMeter::walk_contour(const sweep::Frame& fr) {
  struct Pt {
    double t, g, r, A;
  };
  const auto& P = track_->pieces();
  const auto& E = track_->extrema();
  const double inv = 1.0 / fr.dtheta;
  std::vector<double> ts;
  for (size_t i = 0; i < P.size(); ++i) {
    const TrackPiece& p = P[i];
    const LongCheb& A = areas_[i];
    const uint32_t piece = static_cast<uint32_t>(i);
    auto at = [&](double t) -> Pt {
      if (t == -1.0) return {t, (p.th_a + fr.shift) * inv, p.r_a, 0.0};
      if (t == 1.0) return {t, (p.th_b + fr.shift) * inv, p.r_b, A(1.0)};
      double r, a;
      eval_rA(p.R, A, t, r, a);
      return {t, (p.th_a + p.Th(t) + fr.shift) * inv, p.r_a + r, a};
    };
    auto emit = [&](const Pt& a, const Pt& b) {
      if (a.g == b.g) return;  // a radial stretch: no angular extent
      const int64_t j = static_cast<int64_t>(std::floor(std::min(a.g, b.g)));
      const double jd = static_cast<double>(j);
      Sub s{piece, a.t, b.t, std::clamp(a.g - jd, 0.0, 1.0), std::clamp(b.g - jd, 0.0, 1.0), a.r, b.r, a.A, b.A};
      add_sub(s, j);
    };
    ts.clear();
    ts.push_back(-1.0);
    for (uint32_t k = p.ext_begin; k < p.ext_end; ++k) ts.push_back(E[k]);
    ts.push_back(1.0);
    Pt cur = at(-1.0);
    for (size_t k = 0; k + 1 < ts.size(); ++k) {
      const Pt nxt = at(ts[k + 1]);
      const int dir = nxt.g > cur.g ? 1 : (nxt.g < cur.g ? -1 : 0);
      if (dir != 0) {
        const double lo_g = std::min(cur.g, nxt.g), hi_g = std::max(cur.g, nxt.g);
        const int64_t first = static_cast<int64_t>(std::floor(lo_g)) + 1, last = static_cast<int64_t>(std::ceil(hi_g)) - 1;
        const int64_t count = last - first + 1;
        double hist[3] = {0, 0, 0};
        int nh = 0;
        for (int64_t q = 0; q < count; ++q) {
          const int64_t L = dir > 0 ? first + q : last - q;
          const double Ld = static_cast<double>(L);
          double guess;
          if (nh >= 3)
            guess = 3.0 * hist[0] - 3.0 * hist[1] + hist[2];
          else if (nh == 2)
            guess = 2.0 * hist[0] - hist[1];
          else
            guess = cur.t + (Ld - cur.g) / (nxt.g - cur.g) * (nxt.t - cur.t);
          const double y = Ld * fr.dtheta - fr.shift - p.th_a;
          const double t = solve_level(p.Th, y, cur.t, nxt.t, (cur.g - Ld) * fr.dtheta, guess);
          double r, a;
          eval_rA(p.R, A, t, r, a);
          const Pt lv{t, Ld, p.r_a + r, a};
          emit(cur, lv);
          cur = lv;
          hist[2] = hist[1];
          hist[1] = hist[0];
          hist[0] = t;
          if (nh < 3) ++nh;
        }
      }
      emit(cur, nxt);
      cur = nxt;
    }
  }
  close_visit();
}

void PolarAreaMeter::add_connector(Vec2 a, double ga, Vec2 b, double gb) {
  if (ga == gb) return;  // radial: no angular extent
  const int8_t sg = gb > ga ? 1 : -1;
  const double lo = std::min(ga, gb), hi = std::max(ga, gb);
  for (int64_t j = static_cast<int64_t>(std::floor(lo)); static_cast<double>(j) < hi; ++j) {
    const double jd = static_cast<double>(j);
    const double l0 = std::max(lo - jd, 0.0), l1 = std::min(hi - jd, 1.0);
    if (!(l1 > l0)) continue;
    sweep::Strand s;
    s.kind = sweep::Strand::segment;
    s.sigma = sg;
    s.j = j;
    s.l0 = l0;
    s.l1 = l1;
    s.a = a;
    s.b = b;
    const uint32_t k = key(j);
    extra_.push_back(s);
    extra_next_.push_back(extra_head_[k]);
    extra_head_[k] = static_cast<int32_t>(extra_.size() - 1);
    forced_[k] = 1;
  }
}

double PolarAreaMeter::fast_visit(const Visit& v, double rho) const {
  double s = 0.0;
  const auto& P = track_->pieces();
  for (uint32_t i = v.first; i < v.first + v.count; ++i) {
    const Sub& b = subs_[i];
    const double ra = P[b.piece].r_a;
    const double k = 0.5 * (ra - rho) * (ra + rho) * grid_.dtheta;
    if ((b.r0 - rho) * (b.r1 - rho) < 0.0) {
      const TrackPiece& p = P[b.piece];
      const double t = radius_crossing(p.R, rho - ra, b.t0, b.t1, b.r0 - ra, b.r1 - ra);
      double th, a;
      eval_thA(p.Th, areas_[b.piece], t, th, a);
      const double l = (p.th_a + th + shift_) / grid_.dtheta - static_cast<double>(v.j);
      s += std::abs(a - b.A0 + k * (l - b.l0)) + std::abs(b.A1 - a + k * (b.l1 - l));
    } else {
      s += std::abs(b.A1 - b.A0 + k * (b.l1 - b.l0));
    }
  }
  return s;
}

AreaErrorResult PolarAreaMeter::finish(int64_t n0, int64_t m0) {
  if (!track_) throw std::logic_error("PolarAreaMeter::finish before reset");
  grid_.validate();
  const PolarTrack& tr = *track_;
  const auto& P = tr.pieces();
  const double dr = grid_.dr, dth = grid_.dtheta;
  const int64_t N = grid_.steps_per_rev;

  AreaErrorResult res;
  res.radial_steps = nr_;
  res.angular_steps = arcs_.size();
  // the angular branch: whole turns that bring the path's start next to the start node
  const double th0 = P.front().th_a;
  const double shift = kTwoPi * std::nearbyint((static_cast<double>(m0) * dth - th0) / kTwoPi);
  res.theta_shift = shift;
  shift_ = shift;
  const sweep::Frame fr{dth, shift};

  const int64_t n1 = n0 + n_, m1 = m0 + m_;
  auto check_end = [&](const char* which, int64_t n, int64_t m, double r, double th) {
    const double rho = static_cast<double>(n) * dr, dphi = static_cast<double>(m) * dth - (th + shift);
    const double d = std::sqrt(std::max(0.0, rho * rho + r * r - 2.0 * rho * r * std::cos(dphi)));
    const double tol = 2.0 * std::hypot(dr, std::max(rho, r) * dth) + 1e-12;
    if (!(d <= tol) || !(std::abs(dphi) < std::numbers::pi))
      throw InputError(std::string("the tape does not follow this path: its ") + which + " node (" + std::to_string(n) +
                       ", " + std::to_string(m) + ") is " + num(d * 1e3) + " mm from the path's " + which + " (r = " +
                       num(r * 1e3) + " mm, theta = " + num(th + shift) + " rad); was it made from this job?");
  };
  check_end("start", n0, m0, P.front().r_a, P.front().th_a);
  check_end("end", n1, m1, P.back().r_b, P.back().th_b);

  // sectors: the path's angular range (plus a margin) in grid units
  const double gmin = (tr.theta_min().value + shift) / dth, gmax = (tr.theta_max().value + shift) / dth;
  j_lo_ = static_cast<int64_t>(std::floor(gmin)) - 2;
  j_hi_ = static_cast<int64_t>(std::floor(gmax)) + 2;
  const int64_t span = j_hi_ - j_lo_ + 1;
  if (N > 0 && span >= N) {
    wrap_ = true;
    nkeys_ = N;
    key_lo_ = ((j_lo_ % N) + N) % N;
  } else {
    if (N == 0 && static_cast<double>(span) * dth >= kTwoPi)
      throw InputError("the area error of a path that turns about the machine pole needs a whole number of angular "
                       "steps per revolution (the grid has " + num(kTwoPi / dth, 10) + ")");
    wrap_ = false;
    nkeys_ = span;
  }
  const size_t nk = static_cast<size_t>(nkeys_);
  arc_head_.assign(nk, -1);
  visit_head_.assign(nk, -1);
  extra_head_.assign(nk, -1);
  forced_.assign(nk, 0);
  visits_.clear();
  subs_.clear();
  extra_.clear();
  extra_next_.clear();
  open_ = -1;

  // the staircase's arcs, by sector
  for (size_t i = 0; i < arcs_.size(); ++i) {
    ArcRec& a = arcs_[i];
    a.n += n0;
    const int64_t mb = m0 + a.m;
    a.m = a.dir > 0 ? mb : mb - 1;  // the sector the arc spans
    if (a.m < j_lo_ || a.m > j_hi_)
      throw InputError("the tape does not follow this path: its angular step " + std::to_string(i + 1) +
                       " leaves the path's angular range (node " + std::to_string(a.n) + ", " + std::to_string(mb) + ")");
    const uint32_t k = key(a.m);
    a.next = arc_head_[k];
    arc_head_[k] = static_cast<int32_t>(i);
  }

  walk_contour(fr);

  // connectors close the cycle unless both the path and the staircase close on themselves
  const bool closes = tr.closed() && n_ == 0 &&
                      (N > 0 ? m_ == static_cast<int64_t>(tr.winding()) * N : (m_ == 0 && tr.winding() == 0));
  if (!closes) {
    // straight segments from the staircase's start node to the path's start, and from the path's end to the
    // staircase's end node
    auto node = [&](int64_t n, int64_t m) {
      const double rho = static_cast<double>(n) * dr, phi = static_cast<double>(m) * dth - shift;
      return Vec2{rho * std::cos(phi), rho * std::sin(phi)};
    };
    auto point = [&](double r, double th) { return Vec2{r * std::cos(th), r * std::sin(th)}; };
    add_connector(node(n0, m0), static_cast<double>(m0), point(P.front().r_a, P.front().th_a),
                  (P.front().th_a + shift) / dth);
    add_connector(point(P.back().r_b, P.back().th_b), (P.back().th_b + shift) / dth, node(n1, m1),
                  static_cast<double>(m1));
  }

  const sweep::SectorSolver solver(tr, areas_, fr);
  Neumaier total;
  std::vector<int32_t> vs, as;
  std::vector<sweep::Strand> strands;
  for (size_t k = 0; k < nk; ++k) {
    const int32_t vh = visit_head_[k], ah = arc_head_[k];
    if (vh < 0 && ah < 0 && extra_head_[k] < 0) continue;
    ++res.sectors;
    if (!force_general_ && !forced_[k] && vh >= 0 && ah >= 0) {
      // the common case: one pass of the contour and one arc
      const Visit& v = visits_[static_cast<size_t>(vh)];
      const ArcRec& a = arcs_[static_cast<size_t>(ah)];
      if (v.next < 0 && a.next < 0 && v.full && v.sigma == a.dir) {
        total.add(fast_visit(v, static_cast<double>(a.n) * dr));
        continue;
      }
    }
    vs.clear();
    as.clear();
    for (int32_t v = visit_head_[k]; v >= 0; v = visits_[static_cast<size_t>(v)].next) vs.push_back(v);
    for (int32_t a = arc_head_[k]; a >= 0; a = arcs_[static_cast<size_t>(a)].next) as.push_back(a);
    bool fast = !force_general_ && !forced_[k] && !vs.empty() && vs.size() == as.size();
    for (size_t i = 0; fast && i < vs.size(); ++i) fast = visits_[static_cast<size_t>(vs[i])].full;
    if (fast && vs.size() > 1) {
      // several passes: pair them by radius; exact when each pair's radial range is clear of the others
      std::sort(vs.begin(), vs.end(), [&](int32_t x, int32_t y) {
        return visits_[static_cast<size_t>(x)].rmin < visits_[static_cast<size_t>(y)].rmin;
      });
      std::sort(as.begin(), as.end(), [&](int32_t x, int32_t y) {
        return arcs_[static_cast<size_t>(x)].n < arcs_[static_cast<size_t>(y)].n;
      });
      double prev_hi = -1.0;
      for (size_t i = 0; fast && i < vs.size(); ++i) {
        const Visit& v = visits_[static_cast<size_t>(vs[i])];
        const double rho = static_cast<double>(arcs_[static_cast<size_t>(as[i])].n) * dr;
        const double lo = std::min(v.rmin, rho), hi = std::max(v.rmax, rho);
        fast = lo > prev_hi;
        prev_hi = hi;
      }
    }
    for (size_t i = 0; fast && i < vs.size(); ++i)
      fast = visits_[static_cast<size_t>(vs[i])].sigma == arcs_[static_cast<size_t>(as[i])].dir;
    if (fast) {
      for (size_t i = 0; i < vs.size(); ++i)
        total.add(fast_visit(visits_[static_cast<size_t>(vs[i])],
                             static_cast<double>(arcs_[static_cast<size_t>(as[i])].n) * dr));
      continue;
    }
    ++res.general_sectors;
    strands.clear();
    for (int32_t vi : vs) {
      const Visit& v = visits_[static_cast<size_t>(vi)];
      for (uint32_t i = v.first; i < v.first + v.count; ++i) {
        const Sub& b = subs_[i];
        if (b.l0 == b.l1) continue;
        sweep::Strand s;
        s.kind = sweep::Strand::contour;
        s.j = v.j;
        s.piece = b.piece;
        if (b.l1 > b.l0) {
          s.sigma = 1;
          s.l0 = b.l0, s.l1 = b.l1, s.t0 = b.t0, s.t1 = b.t1, s.r0 = b.r0, s.r1 = b.r1;
        } else {
          s.sigma = -1;
          s.l0 = b.l1, s.l1 = b.l0, s.t0 = b.t1, s.t1 = b.t0, s.r0 = b.r1, s.r1 = b.r0;
        }
        strands.push_back(s);
      }
    }
    for (int32_t ai : as) {
      const ArcRec& a = arcs_[static_cast<size_t>(ai)];
      sweep::Strand s;
      s.kind = sweep::Strand::arc;
      s.sigma = static_cast<int8_t>(-a.dir);  // the cycle runs the staircase backwards
      s.j = a.m;
      s.rho = static_cast<double>(a.n) * dr;
      strands.push_back(s);
    }
    for (int32_t e = extra_head_[k]; e >= 0; e = extra_next_[static_cast<size_t>(e)]) strands.push_back(extra_[static_cast<size_t>(e)]);
    total.add(solver.area(strands));
  }
  res.area_m2 = total.value();
  if (!std::isfinite(res.area_m2)) throw std::logic_error("internal error: the area error is not finite");
  // the recorded steps are now absolute; the meter must be reset before it is used again
  arcs_.clear();
  n_ = m_ = 0;
  nr_ = 0;
  return res;
}

}  // namespace polarcam
