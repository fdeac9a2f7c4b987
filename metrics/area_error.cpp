#include "metrics/area_error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "metrics/area_roots.hpp"

namespace polarcam {
namespace {

using namespace area_roots;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::string num(double v, int prec = 6) { return significant(v, prec); }

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

void StairAreaMeter::reset(sweep::TrackView track, const StairGrid& grid) {
  track_ = std::move(track);
  bound_ = true;
  grid_ = grid;
  sector_area_series(track_, areas_);
  arcs_.clear();
  n_ = m_ = 0;
  nr_ = 0;
}

uint32_t StairAreaMeter::key(int64_t j) const {
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

Vec2 StairAreaMeter::node_point(int64_t h, int64_t g) const {
  if (grid_.geo == sweep::Geometry::cartesian)
    return {static_cast<double>(g) * grid_.width, static_cast<double>(h) * grid_.height};
  const double rho = static_cast<double>(h) * grid_.height, phi = static_cast<double>(g) * grid_.width - shift_;
  return {rho * std::cos(phi), rho * std::sin(phi)};
}

Vec2 StairAreaMeter::path_point(double h, double g) const {
  if (grid_.geo == sweep::Geometry::cartesian) return {g, h};
  return {h * std::cos(g), h * std::sin(g)};
}

void StairAreaMeter::close_visit() {
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

void StairAreaMeter::add_sub(const Sub& s, int64_t j) {
  const int8_t sg = s.l1 > s.l0 ? 1 : -1;
  const double lo = s.h0 < s.h1 ? s.h0 : s.h1, hi = s.h0 < s.h1 ? s.h1 : s.h0;
  if (open_ >= 0) {
    Visit& v = visits_[static_cast<size_t>(open_)];
    if (v.j == j) {
      if (v.sigma != sg) v.sigma = 0;
      ++v.count;
      if (lo < v.hmin) v.hmin = lo;
      if (hi > v.hmax) v.hmax = hi;
      subs_.push_back(s);
      return;
    }
    close_visit();
  }
  open_ = static_cast<int>(visits_.size());
  visits_.push_back(Visit{j, static_cast<uint32_t>(subs_.size()), 1, -1, sg, false, lo, hi});
  subs_.push_back(s);
}

void StairAreaMeter::walk_contour(const sweep::Frame& fr) {
  struct Pt {
    double t, g, h, A;
  };
  const auto& P = track_.pieces;
  const auto& E = *track_.extrema;
  const double inv = 1.0 / fr.width;
  std::vector<double> ts;
  for (size_t i = 0; i < P.size(); ++i) {
    const sweep::PieceView& p = P[i];
    const Cheb& G = *p.G;
    const Cheb& H = *p.H;
    const LongCheb& A = areas_[i];
    const uint32_t piece = static_cast<uint32_t>(i);
    auto at = [&](double t) -> Pt {
      if (t == -1.0) return {t, (p.g_a + fr.shift) * inv, p.h_a, 0.0};
      if (t == 1.0) return {t, (p.g_b + fr.shift) * inv, p.h_b, A(1.0)};
      double h, a;
      eval_rA(H, A, t, h, a);
      return {t, (p.g_a + G(t) + fr.shift) * inv, p.h_a + h, a};
    };
    auto emit = [&](const Pt& a, const Pt& b) {
      if (a.g == b.g) return;  // no extent in the abscissa (radial, or vertical)
      const int64_t j = static_cast<int64_t>(std::floor(std::min(a.g, b.g)));
      const double jd = static_cast<double>(j);
      Sub s{piece, a.t, b.t, std::clamp(a.g - jd, 0.0, 1.0), std::clamp(b.g - jd, 0.0, 1.0), a.h, b.h, a.A, b.A};
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
          const double y = Ld * fr.width - fr.shift - p.g_a;
          const double t = solve_level(G, y, cur.t, nxt.t, (cur.g - Ld) * fr.width, guess);
          double h, a;
          eval_rA(H, A, t, h, a);
          const Pt lv{t, Ld, p.h_a + h, a};
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

void StairAreaMeter::add_connector(Vec2 a, double ga, Vec2 b, double gb) {
  if (ga == gb) return;  // no extent in the abscissa
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

double StairAreaMeter::fast_visit(const Visit& v, double rho) const {
  double s = 0.0;
  const auto& P = track_.pieces;
  const bool polar = grid_.geo == sweep::Geometry::polar;
  for (uint32_t i = v.first; i < v.first + v.count; ++i) {
    const Sub& b = subs_[i];
    const sweep::PieceView& p = P[b.piece];
    const double ha = p.h_a;
    // the integral of the staircase's level minus the piece's base, per unit of lambda
    const double k = (polar ? 0.5 * (ha - rho) * (ha + rho) : ha - rho) * grid_.width;
    if ((b.h0 - rho) * (b.h1 - rho) < 0.0) {
      const double t = radius_crossing(*p.H, rho - ha, b.t0, b.t1, b.h0 - ha, b.h1 - ha);
      double g, a;
      eval_gA(*p.G, areas_[b.piece], t, g, a);
      const double l = (p.g_a + g + shift_) / grid_.width - static_cast<double>(v.j);
      s += std::abs(a - b.A0 + k * (l - b.l0)) + std::abs(b.A1 - a + k * (b.l1 - l));
    } else {
      s += std::abs(b.A1 - b.A0 + k * (b.l1 - b.l0));
    }
  }
  return s;
}

StairAreaResult StairAreaMeter::finish(int64_t n0, int64_t m0) {
  if (!bound_) throw std::logic_error("StairAreaMeter::finish before reset");
  const sweep::TrackView& tr = track_;
  const auto& P = tr.pieces;
  const bool polar = grid_.geo == sweep::Geometry::polar;
  const double dr = grid_.height, dth = grid_.width;
  const int64_t N = polar ? grid_.steps_per_rev : 0;

  StairAreaResult res;
  res.rise_steps = nr_;
  res.run_steps = arcs_.size();
  // polar: the angular branch, whole turns that bring the path's start next to the start node
  const double th0 = P.front().g_a;
  const double shift = polar ? kTwoPi * std::nearbyint((static_cast<double>(m0) * dth - th0) / kTwoPi) : 0.0;
  res.shift = shift;
  shift_ = shift;
  const sweep::Frame fr{dth, shift, grid_.geo};

  auto node_text = [&](int64_t n, int64_t m) {
    return polar ? "(" + std::to_string(n) + ", " + std::to_string(m) + ")"
                 : "(" + std::to_string(m) + ", " + std::to_string(n) + ")";
  };
  const int64_t n1 = n0 + n_, m1 = m0 + m_;
  auto check_end = [&](const char* which, int64_t n, int64_t m, double r, double th) {
    const Vec2 node = node_point(n, m), pt = path_point(r, th);  // both on the track's branch
    const double d = norm(node - pt);
    double tol = 2.0 * std::hypot(dr, dth) + 1e-12;
    bool ok = d <= tol;
    std::string where = "x = " + num(th * 1e3) + " mm, y = " + num(r * 1e3) + " mm";
    if (polar) {
      const double rho = static_cast<double>(n) * dr, dphi = static_cast<double>(m) * dth - (th + shift);
      tol = 2.0 * std::hypot(dr, std::max(rho, r) * dth) + 1e-12;
      ok = d <= tol && std::abs(dphi) < std::numbers::pi;
      where = "r = " + num(r * 1e3) + " mm, theta = " + num(th + shift) + " rad";
    }
    if (!ok)
      throw InputError(std::string(polar ? "the" : "the Cartesian") + " tape does not follow this path: its " + which + " node " + node_text(n, m) +
                       " is " + num(d * 1e3) + " mm from the path's " + which + " (" + where +
                       "); was it made from this job?");
  };
  check_end("start", n0, m0, P.front().h_a, P.front().g_a);
  check_end("end", n1, m1, P.back().h_b, P.back().g_b);

  // sectors: the path's abscissa range (plus a margin) in grid units
  const double gmin = (tr.g_min + shift) / dth, gmax = (tr.g_max + shift) / dth;
  if (!(std::abs(gmin) < 4e18 && std::abs(gmax) < 4e18)) throw InputError("the path is too far from the origin for this grid");
  j_lo_ = static_cast<int64_t>(std::floor(gmin)) - 2;
  j_hi_ = static_cast<int64_t>(std::floor(gmax)) + 2;
  const int64_t span = j_hi_ - j_lo_ + 1;
  if (N > 0 && span >= N) {
    wrap_ = true;
    nkeys_ = N;
    key_lo_ = ((j_lo_ % N) + N) % N;
  } else {
    if (polar && N == 0 && static_cast<double>(span) * dth >= kTwoPi)
      throw InputError("the area error of a path that turns about the machine pole needs a whole number of angular "
                       "steps per revolution (the grid has " + num(kTwoPi / dth, 10) + ")");
    if (span > (int64_t{1} << 31))
      throw InputError("the path spans " + num(static_cast<double>(span), 4) +
                       " grid cells; the area error needs fewer than 2^31");
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

  // the staircase's level strands, by sector
  for (size_t i = 0; i < arcs_.size(); ++i) {
    ArcRec& a = arcs_[i];
    a.n += n0;
    const int64_t mb = m0 + a.m;
    a.m = a.dir > 0 ? mb : mb - 1;  // the sector the level strand spans
    if (a.m < j_lo_ || a.m > j_hi_)
      throw InputError(std::string(polar ? "the" : "the Cartesian") + " tape does not follow this path: its " + std::string(polar ? "angular" : "x") + " step " +
                       std::to_string(i + 1) + " leaves the path's " + (polar ? "angular" : "x") + " range (node " +
                       node_text(a.n, mb) + ")");
    const uint32_t k = key(a.m);
    a.next = arc_head_[k];
    arc_head_[k] = static_cast<int32_t>(i);
  }

  walk_contour(fr);

  // connectors close the cycle unless both the path and the staircase close on themselves
  const bool closes = tr.closed && n_ == 0 &&
                      (N > 0 ? m_ == static_cast<int64_t>(tr.winding) * N : (m_ == 0 && tr.winding == 0));
  if (!closes) {
    // straight segments from the staircase's start node to the path's start, and from the path's end to the
    // staircase's end node
    add_connector(node_point(n0, m0), static_cast<double>(m0), path_point(P.front().h_a, P.front().g_a),
                  (P.front().g_a + shift) / dth);
    add_connector(path_point(P.back().h_b, P.back().g_b), (P.back().g_b + shift) / dth, node_point(n1, m1),
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
      // the common case: one pass of the contour and one level strand
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
      // several passes: pair them by height; exact when each pair's range of height is clear of the others
      std::sort(vs.begin(), vs.end(), [&](int32_t x, int32_t y) {
        return visits_[static_cast<size_t>(x)].hmin < visits_[static_cast<size_t>(y)].hmin;
      });
      std::sort(as.begin(), as.end(), [&](int32_t x, int32_t y) {
        return arcs_[static_cast<size_t>(x)].n < arcs_[static_cast<size_t>(y)].n;
      });
      double prev_hi = -std::numeric_limits<double>::infinity();
      for (size_t i = 0; fast && i < vs.size(); ++i) {
        const Visit& v = visits_[static_cast<size_t>(vs[i])];
        const double rho = static_cast<double>(arcs_[static_cast<size_t>(as[i])].n) * dr;
        const double lo = std::min(v.hmin, rho), hi = std::max(v.hmax, rho);
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
          s.l0 = b.l0, s.l1 = b.l1, s.t0 = b.t0, s.t1 = b.t1, s.h0 = b.h0, s.h1 = b.h1;
        } else {
          s.sigma = -1;
          s.l0 = b.l1, s.l1 = b.l0, s.t0 = b.t1, s.t1 = b.t0, s.h0 = b.h1, s.h1 = b.h0;
        }
        strands.push_back(s);
      }
    }
    for (int32_t ai : as) {
      const ArcRec& a = arcs_[static_cast<size_t>(ai)];
      sweep::Strand s;
      s.kind = sweep::Strand::level;
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

void PolarAreaMeter::reset(const PolarTrack& track, const Grid& grid) {
  grid_ = grid;
  core_.reset(sweep::view_of(track),
              StairGrid{sweep::Geometry::polar, grid.dtheta, grid.dr, grid.steps_per_rev});
}

AreaErrorResult PolarAreaMeter::finish(int64_t n0, int64_t m0) {
  grid_.validate();
  return core_.finish(n0, m0);
}

}  // namespace polarcam
