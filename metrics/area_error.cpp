#include "metrics/area_error.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "digitizer/level_inverse.hpp"
#include "metrics/area_roots.hpp"

namespace polarcam {
namespace {

using namespace area_roots;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::string num(double v, int prec = 6) { return significant(v, prec); }

// Whether a sub whose radius runs from h0 to h1 crosses the level strand at rho (strictly, within the sub).
inline bool crosses(double h0, double h1, double rho) { return (h0 - rho) * (h1 - rho) < 0.0; }

// The part of a sub that stays on one side of its level strand: its Astar from A0 to A1, less the strand's over the
// sub's run dl in l (k: level_factor).
inline double one_side(double A0, double A1, double k, double dl) { return std::abs(A1 - A0 + k * dl); }

// The part of a sub that crosses its level strand at (l, a), l its coordinate from l0 to l1 and a its Astar: the
// two sides, each one_side's measure.
inline double two_sides(double A0, double A1, double k, double l0, double l1, double l, double a) {
  return std::abs(a - A0 + k * (l - l0)) + std::abs(A1 - a + k * (l1 - l));
}

}  // namespace

void StairAreaMeter::SlotIndex::clear() {
  dkeys_.fill(kNone);
  dsize_ = 0;
  std::fill(keys_.begin(), keys_.end(), kNone);
  size_ = 0;
}

void StairAreaMeter::KeyRing::grow() {
  std::vector<uint32_t> b(std::max<size_t>(256, 2 * buf_.size()));
  for (size_t i = 0; i < n_; ++i) b[i] = buf_[(head_ + i) & (buf_.size() - 1)];
  buf_ = std::move(b);
  head_ = 0;
}

void StairAreaMeter::SlotIndex::probe_insert(uint32_t k, uint32_t slot) {
  if (2 * (size_ + 1) > keys_.size()) {  // grow: at most half full
    std::vector<uint32_t> ok = std::move(keys_), ov = std::move(vals_);
    const size_t n = std::max<size_t>(256, 2 * ok.size());
    keys_.assign(n, kNone);
    vals_.assign(n, 0);
    mask_ = n - 1;
    shift_bits_ = 32 - std::countr_zero(n);
    size_ = 0;
    for (size_t i = 0; i < ok.size(); ++i)
      if (ok[i] != kNone) probe_insert(ok[i], ov[i]);
  }
  size_t i = home(k);
  while (keys_[i] != kNone) i = (i + 1) & mask_;
  keys_[i] = k;
  vals_[i] = slot;
  ++size_;
}

void StairAreaMeter::SlotIndex::probe_erase(uint32_t k) {
  size_t i = home(k);
  while (keys_[i] != k) i = (i + 1) & mask_;
  // backward shift: move up each later key of the run whose home is not between the hole and it
  for (size_t j = (i + 1) & mask_; keys_[j] != kNone; j = (j + 1) & mask_) {
    const size_t h = home(keys_[j]);
    if (((j - h) & mask_) >= ((j - i) & mask_)) {
      keys_[i] = keys_[j];
      vals_[i] = vals_[j];
      i = j;
    }
  }
  keys_[i] = kNone;
  --size_;
}

void StairAreaMeter::reset(sweep::TrackView track, const StairGrid& grid) {
  track_ = std::move(track);
  bound_ = true;
  grid_ = grid;
  sector_area_series(track_, areas_);
  pair_[0] = pair_[1] = kNoPiece;  // the pieces' series are new
  for (uint32_t& q : quad_) q = kNoPiece;
  fit_piece_ = SIZE_MAX;
  arcs_.clear();
  n_ = m_ = 0;
  nr_ = 0;
  nrun_ = 0;
  subs_out_ = 0;
  stream_ = failed_ = false;
  range_error_.clear();
  slot_of_.clear();
  free_slots_.clear();
  for (uint32_t i = 0; i < slots_.size(); ++i) free_slots_.push_back(i);
  order_.clear();
  done_.clear();
  done_lo_ = 1, done_hi_ = 0;
  run_lo_ = 1, run_hi_ = 0;
  pinned_.clear();
  peak_slots_ = 0;
  pass_on_ = false;
  pass_clear();
  walk_.done = true;
  open_ = -1;
  imp_.on = imp_.failed = imp_.walked = imp_.dense = false;
  imp_.part.clear();
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

bool StairAreaMeter::full_visit(int8_t sigma, const Sub& first, const Sub& last) {
  return sigma != 0 && ((first.l0 == 0.0 && last.l1 == 1.0) || (first.l0 == 1.0 && last.l1 == 0.0));
}

void StairAreaMeter::close_visit() {
  if (open_ < 0) return;
  if (stream_) {
    Slot& sl = slots_[open_slot_];
    Visit& v = sl.visits[static_cast<size_t>(open_)];
    const Sub& a = sl.subs[v.first];
    const Sub& b = sl.subs[v.first + v.count - 1];
    v.full = full_visit(v.sigma, a, b);
    open_ = -1;
    return;
  }
  Visit& v = visits_[static_cast<size_t>(open_)];
  const Sub& a = subs_[v.first];
  const Sub& b = subs_[v.first + v.count - 1];
  v.full = full_visit(v.sigma, a, b);
  const uint32_t k = key(v.j);
  v.next = visit_head_[k];
  visit_head_[k] = open_;
  open_ = -1;
}

void StairAreaMeter::add_sub(const Sub& s, int64_t j, int8_t sg, double lo, double hi) {
  ++subs_out_;
  if (stream_) {
    if (failed_) return;
    const uint32_t k = key(j);
    walk_key_ = k;
    if (pass_on_ && pass_sub(s, j, sg, k)) return;
    if (open_ >= 0) {
      Slot& o = slots_[open_slot_];
      Visit& v = o.visits[static_cast<size_t>(open_)];
      if (v.j == j) {
        if (v.sigma != sg) v.sigma = 0;
        ++v.count;
        if (lo < v.hmin) v.hmin = lo;
        if (hi > v.hmax) v.hmax = hi;
        o.subs.push_back(s);
        return;
      }
      close_visit();
    }
    Slot* sl = stream_slot(k);
    if (!sl) return;
    open_slot_ = static_cast<uint32_t>(sl - slots_.data());
    open_ = static_cast<int>(sl->visits.size());
    sl->visits.push_back(Visit{j, static_cast<uint32_t>(sl->subs.size()), 1, -1, sg, false, lo, hi});
    sl->subs.push_back(s);
    return;
  }
  if (imp_.dense) {
    dense_sub(s, j, sg, lo, hi);
    return;
  }
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

StairAreaMeter::WalkPt StairAreaMeter::walk_at(double t) const {
  const sweep::PieceView& p = track_.pieces[walk_.piece];
  const double inv = 1.0 / frame_.width;
  if (t == -1.0) return {t, (p.g_a + frame_.shift) * inv, p.h_a, 0.0};
  const LongCheb& A = areas_[walk_.piece];
  if (t == 1.0) return {t, (p.g_b + frame_.shift) * inv, p.h_b, A(1.0)};
  double h, a;
  eval_rA(*p.H, A, t, h, a);
  return {t, (p.g_a + (*p.G)(t) + frame_.shift) * inv, p.h_a + h, a};
}

void StairAreaMeter::walk_emit(const WalkPt& a, const WalkPt& b) {
  if (a.g == b.g) return;  // no extent in the abscissa (radial, or vertical)
  const int64_t j = static_cast<int64_t>(std::floor(std::min(a.g, b.g)));
  const double jd = static_cast<double>(j);
  const double l0 = std::clamp(a.g - jd, 0.0, 1.0), l1 = std::clamp(b.g - jd, 0.0, 1.0);
  const Sub s{static_cast<uint32_t>(walk_.piece), a.t, b.t, l0, l1, a.h, b.h, a.A, b.A};
  const int8_t sg = l1 > l0 ? 1 : -1;
  // the direction and the radial range from the points themselves, not read back from the sub just stored
  const double lo = a.h < b.h ? a.h : b.h, hi = a.h < b.h ? b.h : a.h;
  if (imp_.dense && std::abs(l1 - l0) == 1.0 && dense_full(s, j, sg)) return;
  add_sub(s, j, sg, lo, hi);
}

bool StairAreaMeter::dense_full(const Sub& s, int64_t j, int8_t sg) {
  // a sub from one edge of its sector to the other on a path monotone in angle is the whole of the sector's visit
  // (the sub before it ended on this sector's first edge, in the sector before, whose visit is closed here): with
  // the sector's one level strand at the front of the queue, in its direction, it is measured at once, as
  // dense_visit would; otherwise it opens a visit as any sub
  Implied& im = imp_;
  dense_close();
  const size_t a0 = im.head;
  if (!(a0 < im.arcs.size() && im.arcs[a0].j == j && im.arcs[a0].dir == sg &&
        (a0 + 1 == im.arcs.size() || im.arcs[a0 + 1].j != j)))
    return false;
  im.head = a0 + 1;
  dense_part(&s, 1, im.arcs[a0], j);
  return true;
}

void StairAreaMeter::walk_solve(const Span& s) {
  Walk& w = walk_;
  const sweep::PieceView& p = track_.pieces[w.piece];
  double lo = s.ta, glo = s.ga;
  RootHistory hist;
  for (int64_t q = s.j0; q < s.j1; ++q) {
    const double Ld = static_cast<double>(walk_level(q));
    // Newton's method from the extrapolation of the last edges (the chord to the stretch's end at first)
    const double guess = hist.n >= 2 ? hist.guess(0.0) : lo + (Ld - glo) / (s.gb - glo) * (s.tb - lo);
    const double y = Ld * frame_.width - frame_.shift - p.g_a;
    const double t = solve_level(*p.G, y, lo, s.tb, (glo - Ld) * frame_.width, guess);
    double h, a;
    eval_rA(*p.H, areas_[w.piece], t, h, a);
    const WalkPt lv{t, Ld, p.h_a + h, a};
    w.buf.push_back(lv);
    lo = lv.t;
    glo = Ld;
    hist.push(lv.t);
  }
}

namespace {

// The series c (degree n) at the points z[0..cnt) into out (area_roots::clenshaw_many4 or clenshaw_many2: the same
// values). z is padded with zeros to a multiple of sixteen, out sized to match.
void clenshaw_many(const double* c, int n, std::vector<double>& zv, size_t cnt, std::vector<double>& outv) {
  zv.resize(cnt + 16);
  std::fill(zv.begin() + static_cast<std::ptrdiff_t>(cnt), zv.end(), 0.0);
  outv.resize(cnt + 16);
  if (area_roots::has_avx())
    area_roots::clenshaw_many4(c, n, zv.data(), cnt, outv.data());
  else
    area_roots::clenshaw_many2(c, n, zv.data(), cnt, outv.data());
}

}  // namespace

bool StairAreaMeter::walk_fit(const Span& s) {
  Walk& w = walk_;
  const sweep::PieceView& p = track_.pieces[w.piece];
  const LongCheb& A = areas_[w.piece];
  const Cheb& G = *p.G;
  const Cheb& H = *p.H;
  // t, H and Astar less their values at ta: the fits keep the digits of the stretch's own variation
  double hb, ab;
  eval_rA(H, A, s.ta, hb, ab);
  // the fit's samples: four at a time where the processor has AVX (eval_g_rA4: the same values)
  const bool avx = area_roots::has_avx();
  if (avx && fit_piece_ != w.piece) {
    area_roots::prepare_fit(fit_series_, G, H, A);
    fit_piece_ = w.piece;
  }
  auto sample = [&](const double* t, int n, double* y, double* v) {
    double h[kChebMaxDegree + 1], a[kChebMaxDegree + 1];
    if (avx)
      area_roots::eval_g_rA4(fit_series_, t, n, y, h, a);
    else
      for (int i = 0; i < n; ++i) {
        y[i] = G(t[i]);
        eval_rA(H, A, t[i], h[i], a[i]);
      }
    for (int i = 0; i < n; ++i) {
      v[3 * i] = t[i] - s.ta;
      v[3 * i + 1] = h[i] - hb;
      v[3 * i + 2] = a[i] - ab;
    }
  };
  double yc, ik;
  Cheb f[3];
  if (!fit_inverse<3>(sample, s.ta, s.tb, w.tol, yc, ik, f)) return false;
  // the edges: the three series at each edge's z
  const double* c[3] = {f[0].c.data(), f[1].c.data(), f[2].c.data()};
  const double base_y = frame_.shift + p.g_a;
  auto z_of = [&](double level) {  // an abscissa level's z
    const double y = level * frame_.width - base_y;
    return std::clamp((y - yc) * ik, -1.0, 1.0);
  };
  // each series at every edge's z in turn, eight edges at a time (clenshaw_many)
  const size_t cnt = static_cast<size_t>(s.j1 - s.j0);
  auto& ez = w.z;
  ez.resize(cnt);
  for (size_t i = 0; i < cnt; ++i) ez[i] = z_of(static_cast<double>(walk_level(s.j0 + static_cast<int64_t>(i))));
  // the radius and Astar at every edge; t (the first series) at every edge where the walk takes the edges one by
  // one (all_edges), at the first and the last alone where the stretch's columns are measured here (end_edge: the
  // same operations for one point, the same values)
  for (int k = 1; k < 3; ++k) clenshaw_many(c[k], f[k].deg, ez, cnt, w.r[k]);
  const double *r1 = w.r[1].data(), *r2 = w.r[2].data();
  auto edge_at = [&](size_t i, double r0) -> WalkPt {
    const int64_t q = s.j0 + static_cast<int64_t>(i);
    return {std::clamp(s.ta + r0, s.ta, s.tb), static_cast<double>(walk_level(q)), p.h_a + (hb + r1[i]), ab + r2[i]};
  };
  auto all_edges = [&] {
    clenshaw_many(c[0], f[0].deg, ez, cnt, w.r[0]);
    for (size_t i = 0; i < cnt; ++i) w.buf.push_back(edge_at(i, w.r[0][i]));
  };
  auto end_edge = [&](size_t i) { return edge_at(i, area_roots::clenshaw_one(c[0], f[0].deg, ez[i])); };
  if (!imp_.on) {
    all_edges();
    return true;
  }
  // the radius at the half levels from the same fit: hl (exact: the fit at each half level's z; the dense columns'
  // below)
  const std::vector<double>& L = half_levels(s);
  const size_t nl = L.size();
  auto& hl = imp_.h;
  hl.resize(nl);
  auto exact_levels = [&](size_t from, size_t to) {
    if (from >= to) return;
    auto& z = imp_.z;
    z.resize(to - from);
    for (size_t i = from; i < to; ++i) z[i - from] = z_of(L[i]);
    auto& r = w.r[3];
    clenshaw_many(c[1], f[1].deg, z, to - from, r);
    for (size_t i = from; i < to; ++i) hl[i] = p.h_a + (hb + r[i - from]);
  };
  // Dense: the columns between two edges of the stretch, each a sub from ray to ray under the level strand of its
  // half level, are measured here at once, as walk_next, imply_arc and dense_full would one by one (the same parts,
  // in the same sectors: the sum in key order is unchanged). The walk is handed the first edge and the last; the
  // half levels before and after those columns make their level strands as before.
  // column i runs from edge i to edge i + 1; its sector is the lower of their levels
  auto column = [&](size_t i) { return walk_level(s.j0 + static_cast<int64_t>(i)) - (w.dir > 0 ? 0 : 1); };
  size_t k0 = nl;  // the half level of column 0
  if (imp_.dense && cnt >= 3 && nl > 0) {
    const double l_first = static_cast<double>(column(0)) + 0.5;
    const double k = w.dir > 0 ? l_first - L[0] : L[0] - l_first;
    if (k >= 0.0 && k + static_cast<double>(cnt - 1) <= static_cast<double>(nl)) {
      k0 = static_cast<size_t>(k);
      if (!(L[k0] == l_first)) k0 = nl;
    }
  }
  size_t done = 0;
  if (k0 < nl) {
    exact_levels(0, k0);
    exact_levels(k0 + cnt - 1, nl);
    for (; done < k0; ++done) imply_arc(hl[done]);
    // the staircase's next level strand must be that of column 0 (as dense_full requires)
    if (imp_.failed || imp_.g0 + m_ - (w.dir > 0 ? 0 : 1) != column(0)) {
      exact_levels(k0, k0 + cnt - 1);
      k0 = nl;
    }
  } else {
    exact_levels(0, nl);
  }
  if (k0 >= nl) {
    for (; done < nl; ++done) imply_arc(hl[done]);
    all_edges();
    return true;
  }
  const double dr = grid_.height, inv = imp_.inv_height;
  // each column is crossed from ray to ray: l runs from 0 to 1 going up, from 1 to 0 going down (walk_emit's clamps
  // of exact levels)
  const double l0 = w.dir > 0 ? 0.0 : 1.0, l1 = 1.0 - l0;
  // The columns that cross their level: the crossing on the fits (fit_crossings), sixteen at a time, the fits'
  // coefficients laid out for the vectors at the stretch's first crossing; the part split there (crossed_part's
  // sum).
  struct Column {
    uint32_t key;
    double k, A0, A1;
  };
  Column xc[area_roots::FitCrossings::kMax];
  area_roots::FitCrossings xf;
  xf.width = grid_.width;
  const bool polar = grid_.geo == sweep::Geometry::polar;
  const area_roots::SeriesBounds bounds = area_roots::series_bounds(f[1]);  // the radius's fit's
  area_roots::FitCrossingSeries<area_roots::Lane4> fit4;
  area_roots::FitCrossingSeries<Lane2> fit2;
  size_t nx = 0;
  bool prepared = false;
  auto crossings = [&] {
    if (nx == 0) return;
    xf.n = static_cast<int>(nx);
    if (avx) {
      if (!prepared) area_roots::prepare_fit_crossings(fit4, f[1], f[2], bounds);
      area_roots::fit_crossings(fit4, xf);
    } else {
      if (!prepared) area_roots::prepare_fit_crossings(fit2, f[1], f[2], bounds);
      area_roots::fit_crossings(fit2, xf);
    }
    prepared = true;
    for (size_t q = 0; q < nx; ++q) {
      const Column& x = xc[q];
      // l between the column's edges, linear in z as the abscissa is: not from the abscissa itself, whose
      // rounding (some 1e-16 rad of an angle of several radians) would be a large part of a step's width
      const double dz = xf.z1[q] - xf.z0[q];
      const double l = dz != 0.0 ? l0 + ((xf.z[q] - xf.z0[q]) / dz) * (l1 - l0) : 0.5;
      imp_.part[x.key] = two_sides(x.A0, x.A1, x.k, l0, l1, l, ab + xf.a[q]);
    }
    nx = 0;
  };
  w.buf.push_back(end_edge(0));
  // each column's level (nearest_node's, all at once); where one is too near a rounding boundary, the staircase is
  // discarded and the digitizer measures this pole
  auto& levels = imp_.rho;
  levels.resize(cnt - 1);
  // the columns' half levels are their middles in z: the radius there from the edges' values (midpoint_values),
  // within midpoint_error of the fit, which the nearest rule's margin takes in; the fit itself where there are
  // fewer than four edges
  double margin = imp_.margin;
  if (cnt >= 4) {
    area_roots::midpoint_values(r1, cnt, p.h_a, hb, hl.data() + k0);
    const double w_edges = std::max(std::abs(ez[1] - ez[0]), std::abs(ez[cnt - 1] - ez[cnt - 2]));
    margin += area_roots::midpoint_error(bounds, w_edges) * inv;
  } else {
    exact_levels(k0, k0 + cnt - 1);
  }
  if (!(avx ? area_roots::nearest_levels_avx : area_roots::nearest_levels)(hl.data() + k0, cnt - 1, inv, margin, dr,
                                                                          levels.data()))
    imp_.failed = true;
  for (size_t i = 0; i + 1 < cnt; ++i) {
    // the column from edge i to edge i + 1: their radii and Astar
    const double ha = p.h_a + (hb + r1[i]), hb1 = p.h_a + (hb + r1[i + 1]), Aa = ab + r2[i], Ab = ab + r2[i + 1];
    const double rho = levels[i];
    const uint32_t key_j = key(column(i));
    const double k = level_factor(p.h_a, rho);
    if (crosses(ha, hb1, rho)) {
      xf.z0[nx] = ez[i], xf.z1[nx] = ez[i + 1], xf.h0[nx] = r1[i], xf.h1[nx] = r1[i + 1];
      // the four edges of the column's cubic: its own and one on each side, or the four at the stretch's end
      const size_t e0 = i == 0 ? 0 : (i + 2 < cnt ? i - 1 : cnt - 4);
      for (size_t e = 0; e < 4; ++e) xf.v[e][nx] = r1[e0 + e];
      xf.ua[nx] = static_cast<double>(i - e0);
      xf.y[nx] = (rho - p.h_a) - hb;
      // the crossing's budget (FitCrossings): a thousandth of a unit in the last place of the part's values
      xf.hf[nx] = polar ? std::max(std::abs(ha), std::abs(hb1)) : 1.0;
      xf.bud[nx] = cnt >= 4 ? 0x1p-62 * std::max({std::abs(Aa), std::abs(Ab), std::abs(k)}) : 0.0;
      xc[nx] = Column{key_j, k, Aa, Ab};
      if (++nx == area_roots::FitCrossings::kMax) crossings();
    } else {
      imp_.part[key_j] = one_side(Aa, Ab, k, l1 - l0);
    }
  }
  crossings();
  // each column an angular step of the staircase, and a sub of the walk
  const int64_t ncol = static_cast<int64_t>(cnt) - 1;
  m_ += w.dir * ncol;
  nrun_ += static_cast<uint64_t>(ncol);
  subs_out_ += static_cast<uint64_t>(ncol);
  w.buf.push_back(end_edge(cnt - 1));
  w.jump = 1;
  w.jump_q = ncol;
  for (done = k0 + cnt - 1; done < nl; ++done) imply_arc(hl[done]);
  return true;
}

// ---- the nearest staircase without the digitizer (imply_nearest)

bool StairAreaMeter::nearest_node(double f, int64_t& n) const {
  double fl;
  const bool clear = area_roots::nearest_clear(f, imp_.margin, fl);
  if (!(std::abs(fl) < 4e18)) return false;  // not a node (or not finite)
  n = static_cast<int64_t>(fl);
  return clear;
}

const std::vector<double>& StairAreaMeter::half_levels(const Span& s) {
  // the half levels l0 + dl i while l <= gb going up (l > gb going down): exact half-integers, each formed from the
  // count i, not from the level before (no chain of additions)
  auto& L = imp_.L;
  L.clear();
  if (walk_.dir == 0) return L;
  const double dl = walk_.dir > 0 ? 1.0 : -1.0;
  const double l0 = std::floor(s.ga + 0.5 * dl) + 0.5;
  auto inside = [&](size_t i) {
    const double l = l0 + dl * static_cast<double>(i);
    return walk_.dir > 0 ? l <= s.gb : l > s.gb;
  };
  // the count: from the distance to gb, then the levels at its ends checked themselves (the first outside, the last
  // inside), so that it does not rest on the rounding of the distance
  const double span = walk_.dir > 0 ? s.gb - l0 : l0 - s.gb;
  if (!(span < 1e15)) throw std::logic_error("internal error: a stretch of the area walk spans too many levels");
  size_t n = span >= 0.0 ? static_cast<size_t>(span) + 1 : 0;
  while (n > 0 && !inside(n - 1)) --n;
  while (inside(n)) ++n;
  L.resize(n);
  double* out = L.data();
  for (size_t i = 0; i < n; ++i) out[i] = l0 + dl * static_cast<double>(i);
  return L;
}

template <class HAt>
void StairAreaMeter::imply_levels(const Span& s, HAt&& h_at) {
  const std::vector<double>& L = half_levels(s);
  if (L.empty()) return;
  imp_.h.resize(L.size());
  h_at(L.data(), L.size(), imp_.h.data());
  for (size_t i = 0; i < L.size(); ++i) imply_arc(imp_.h[i]);
}

void StairAreaMeter::imply_solve(const Span& s) {
  const sweep::PieceView& p = track_.pieces[walk_.piece];
  imply_levels(s, [&](const double* L, size_t cnt, double* out) {
    double lo = s.ta, glo = s.ga;
    for (size_t i = 0; i < cnt; ++i) {
      const double y = L[i] * frame_.width - frame_.shift - p.g_a;
      const double guess = lo + (L[i] - glo) / (s.gb - glo) * (s.tb - lo);
      const double t = solve_level(*p.G, y, lo, s.tb, (glo - L[i]) * frame_.width, guess);
      out[i] = p.h_a + (*p.H)(t);
      lo = t;
      glo = L[i];
    }
  });
}

void StairAreaMeter::imply_arc(double h) {
  // the radius in steps as the digitizer forms it (times the inverse of the step), its nearest node (a walk that
  // has failed is discarded: it need not go on recording)
  int64_t n;
  if (!nearest_node(h * imp_.inv_height, n)) {
    imp_.failed = true;
    return;
  }
  // recorded as run() records a step: the node before it, relative to the start (dense: waiting for its sector's
  // visit, the sector floor(level) = the node before the step going up, the node after it going down)
  if (imp_.dense)
    imp_.arcs.push_back({n - imp_.h0, m_, imp_.g0 + m_ - (walk_.dir > 0 ? 0 : 1), static_cast<int8_t>(walk_.dir)});
  else
    arcs_.push_back({n - imp_.h0, m_, -1, static_cast<int8_t>(walk_.dir)});
  m_ += walk_.dir;
  ++nrun_;
}

void StairAreaMeter::imply_point(const WalkPt& p) {
  int64_t n, m;
  if (!nearest_node(p.h * imp_.inv_height, n) || !nearest_node(p.g, m)) {
    imp_.failed = true;
    return;
  }
  nr_ += static_cast<uint64_t>(n > imp_.n ? n - imp_.n : imp_.n - n);
  imp_.n = n;
  n_ = n - imp_.h0;
  if (m != imp_.g0 + m_) imp_.failed = true;
}

bool StairAreaMeter::imply_nearest(int64_t h0, int64_t g0, double margin) {
  if (!bound_) throw std::logic_error("StairAreaMeter::imply_nearest before reset");
  if (stream_ || !arcs_.empty() || nr_ != 0 || nrun_ != 0)
    throw std::logic_error("StairAreaMeter::imply_nearest after steps were recorded");
  set_shift(g0);
  prepare_recorded();
  imp_.on = true;
  imp_.failed = imp_.walked = false;
  imp_.margin = margin;
  imp_.h0 = imp_.n = h0;
  imp_.g0 = g0;
  imp_.inv_height = 1.0 / grid_.height;
  imp_.dir = force_general_ ? 0 : path_direction();
  imp_.dense = imp_.dir != 0;
  imp_.arcs.clear();
  imp_.head = 0;
  imp_.open = false;
  dense_n_ = 0;
  if (imp_.dense) imp_.part.assign(static_cast<size_t>(nkeys_), std::numeric_limits<double>::quiet_NaN());
  walk_start();
  if (nr_ != 0) imp_.failed = true;  // the path's start is not on the start node
  while (walk_next()) {
  }
  if (imp_.dense) {
    dense_close();
    dense_flush();
    // every level strand has met its sector's visit
    if (imp_.head != imp_.arcs.size()) imp_.failed = true;
  }
  imp_.on = false;
  imp_.dense = false;
  if (imp_.failed) {
    imp_.part.clear();
    arcs_.clear();
    n_ = m_ = 0;
    nr_ = nrun_ = 0;
    return false;
  }
  imp_.walked = true;
  return true;
}

void StairAreaMeter::walk_refill() {
  // A stretch of at least kMinFit edges is fitted (at most kMaxFit at once) and halved where the fit is refused;
  // the edges of shorter stretches are solved one by one.
  constexpr int64_t kMinFit = 48, kMaxFit = 2048;
  Walk& w = walk_;
  const sweep::PieceView& p = track_.pieces[w.piece];
  w.buf.clear();
  w.jump = std::numeric_limits<size_t>::max();
  w.bpos = 0;
  while (w.buf.empty() && !w.spans.empty()) {
    const Span s = w.spans.back();
    w.spans.pop_back();
    const int64_t n = s.j1 - s.j0;
    if (n <= 0) {
      if (imp_.on) imply_solve(s);
      continue;
    }
    if (n >= kMinFit) {
      if (n <= kMaxFit && walk_fit(s)) break;
      const double tm = 0.5 * (s.ta + s.tb);
      if (s.depth < 40 && tm > s.ta && tm < s.tb) {
        const double gm = std::clamp((p.g_a + (*p.G)(tm) + frame_.shift) / frame_.width, std::min(s.ga, s.gb),
                                     std::max(s.ga, s.gb));
        // the edges up to and including gm go to the first half
        int64_t jm = w.dir > 0 ? static_cast<int64_t>(std::floor(gm)) - w.first + 1
                               : w.last - static_cast<int64_t>(std::ceil(gm)) + 1;
        jm = std::clamp(jm, s.j0, s.j1);
        w.spans.push_back(Span{tm, s.tb, gm, s.gb, jm, s.j1, s.depth + 1});
        w.spans.push_back(Span{s.ta, tm, s.ga, gm, s.j0, jm, s.depth + 1});
        continue;
      }
    }
    walk_solve(s);
    if (imp_.on) imply_solve(s);
  }
  if (w.buf.empty()) throw std::logic_error("internal error: the area walk lost the edges of a segment");
}

void StairAreaMeter::walk_segment_start() {
  Walk& w = walk_;
  w.nxt = walk_at(w.ts[w.seg + 1]);
  w.dir = w.nxt.g > w.cur.g ? 1 : (w.nxt.g < w.cur.g ? -1 : 0);
  w.q = w.count = 0;
  w.spans.clear();
  w.buf.clear();
  w.jump = std::numeric_limits<size_t>::max();
  w.bpos = 0;
  if (w.dir != 0) {
    const double lo_g = std::min(w.cur.g, w.nxt.g), hi_g = std::max(w.cur.g, w.nxt.g);
    w.first = static_cast<int64_t>(std::floor(lo_g)) + 1;
    w.last = static_cast<int64_t>(std::ceil(hi_g)) - 1;
    w.count = w.last - w.first + 1;
    w.spans.push_back(Span{w.cur.t, w.nxt.t, w.cur.g, w.nxt.g, 0, w.count, 0});
  }
}

void StairAreaMeter::walk_piece_start() {
  Walk& w = walk_;
  const sweep::PieceView& p = track_.pieces[w.piece];
  const auto& E = *track_.extrema;
  w.ts.clear();
  w.ts.push_back(-1.0);
  for (uint32_t k = p.ext_begin; k < p.ext_end; ++k) w.ts.push_back(E[k]);
  w.ts.push_back(1.0);
  w.seg = 0;
  // the fits' tolerances: eight units of rounding of t, and of the radius and area series' evaluation
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const LongCheb& A = areas_[w.piece];
  double sh = std::abs(p.h_a), sa = 0.0;
  for (int k = 0; k <= p.H->deg; ++k) sh += std::abs(p.H->c[static_cast<size_t>(k)]);
  for (int k = 0; k <= A.deg; ++k) sa += std::abs(A.c[static_cast<size_t>(k)]);
  w.tol[0] = 64.0 * eps;
  w.tol[1] = 8.0 * eps * sh;
  w.tol[2] = 16.0 * eps * sa + std::numeric_limits<double>::min();
  w.cur = walk_at(-1.0);
  if (imp_.on) imply_point(w.cur);
  walk_segment_start();
}

void StairAreaMeter::walk_start() {
  walk_.done = track_.pieces.empty();
  walk_.piece = 0;
  if (!walk_.done) walk_piece_start();
}

bool StairAreaMeter::walk_next() {
  Walk& w = walk_;
  if (w.done) return false;
  if (w.q < w.count) {
    if (w.bpos == w.buf.size()) walk_refill();
    const size_t at = w.bpos++;
    const WalkPt lv = w.buf[at];
    if (at == w.jump) {  // the columns up to this edge were measured by walk_fit
      w.cur = lv;
      w.q += w.jump_q;
      return true;
    }
    walk_emit(w.cur, lv);
    w.cur = lv;
    ++w.q;
    return true;
  }
  if (imp_.on) {
    // the stretches left hold no edge, at most a half level each
    while (!w.spans.empty()) {
      const Span s = w.spans.back();
      w.spans.pop_back();
      imply_solve(s);
    }
    imply_point(w.nxt);
  }
  walk_emit(w.cur, w.nxt);
  w.cur = w.nxt;
  ++w.seg;
  if (w.seg + 1 < w.ts.size()) {
    walk_segment_start();
  } else if (++w.piece < track_.pieces.size()) {
    walk_piece_start();
  } else {
    w.done = true;
    close_visit();
  }
  return true;
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
    if (stream_) {
      Slot* sl = stream_slot(k);
      if (!sl) return;
      sl->extra.push_back(s);
      sl->forced = true;
      continue;
    }
    extra_.push_back(s);
    extra_next_.push_back(extra_head_[k]);
    extra_head_[k] = static_cast<int32_t>(extra_.size() - 1);
    forced_[k] = 1;
  }
}

double StairAreaMeter::level_factor(double ha, double rho) const {
  return (grid_.geo == sweep::Geometry::polar ? 0.5 * (ha - rho) * (ha + rho) : ha - rho) * grid_.width;
}

void StairAreaMeter::start_crossing(const Sub& b, double rho, RadiusCrossing& c) const {
  const double ha = track_.pieces[b.piece].h_a;
  c.start(rho - ha, b.t0, b.t1, b.h0 - ha, b.h1 - ha);
}

double StairAreaMeter::sub_part(const Sub& b, double rho, double jd) const {
  if (!crosses(b.h0, b.h1, rho)) return one_side(b.A0, b.A1, level_factor(track_.pieces[b.piece].h_a, rho), b.l1 - b.l0);
  const sweep::PieceView& p = track_.pieces[b.piece];
  RadiusCrossing c;
  start_crossing(b, rho, c);
  run_crossing(*p.H, c);
  double g, a;
  eval_gA(*p.G, areas_[b.piece], c.t, g, a);
  return crossed_part(b, rho, jd, g, a);
}

double StairAreaMeter::fast_visit(const Sub* subs, size_t count, double rho, double jd) const {
  double s = 0.0;
  for (size_t i = 0; i < count; ++i) s += sub_part(subs[i], rho, jd);
  return s;
}

double StairAreaMeter::crossed_part(const Sub& b, double rho, double jd, double g, double a) const {
  const sweep::PieceView& p = track_.pieces[b.piece];
  const double k = level_factor(p.h_a, rho);
  const double l = (p.g_a + g + shift_) / grid_.width - jd;
  return two_sides(b.A0, b.A1, k, b.l0, b.l1, l, a);
}

inline void StairAreaMeter::add_total(double x) {
  if (pending_.empty())
    total_.add(x);
  else
    pending_.push_back({x, -1});
}

void StairAreaMeter::add_visit(const Visit& v, double rho, const std::vector<Sub>& subs) {
  if (v.count == 1) {
    add_one(subs[v.first], rho, v.j);
    return;
  }
  add_total(fast_visit(subs.data() + v.first, v.count, rho, static_cast<double>(v.j)));
}

void StairAreaMeter::add_one(const Sub& b, double rho, int64_t j) {
  if (crosses(b.h0, b.h1, rho)) {
    pending_.push_back({0.0, static_cast<int32_t>(crossings_.size())});
    crossings_.push_back({b, rho, static_cast<double>(j)});
    if (crossings_.size() == crossing_batch()) flush_pending();
    return;
  }
  add_total(sub_part(b, rho, static_cast<double>(j)));  // (fast_visit's 0 + the one part: the part itself)
}

size_t StairAreaMeter::crossing_batch() {
  return area_roots::has_avx() ? 4 : 2;  // four at a time where the processor has AVX (the same values either way)
}

void StairAreaMeter::crossing_parts(const Crossing* x, size_t count, double part[4]) {
  size_t i = 0;
  if (count == 4) {
    crossing_quad(x, part);
    i = 4;
  }
  for (; i + 2 <= count; i += 2) crossing_pair(x[i], x[i + 1], part + i);
  if (i < count) part[i] = sub_part(x[i].b, x[i].rho, x[i].jd);
}

void StairAreaMeter::flush_pending() {
  double part[4] = {0.0, 0.0, 0.0, 0.0};
  crossing_parts(crossings_.data(), crossings_.size(), part);
  for (const Pending& e : pending_) total_.add(e.crossing >= 0 ? part[e.crossing] : e.value);
  pending_.clear();
  crossings_.clear();
}

void StairAreaMeter::crossing_pair(const Crossing& x0, const Crossing& x1, double part[2]) {
  const auto& P = track_.pieces;
  const sweep::PieceView &p0 = P[x0.b.piece], &p1 = P[x1.b.piece];
  RadiusCrossing c0, c1;
  start_crossing(x0.b, x0.rho, c0);
  start_crossing(x1.b, x1.rho, c1);
  if (x0.b.piece != pair_[0] || x1.b.piece != pair_[1]) {
    prepare_pair(pair_series_, *p0.H, *p1.H, *p0.G, areas_[x0.b.piece], *p1.G, areas_[x1.b.piece]);
    pair_[0] = x0.b.piece, pair_[1] = x1.b.piece;
  }
  radius_crossing2(pair_series_, *p0.H, *p1.H, c0, c1);
  Lane2 g, a;
  eval_rA2(pair_series_, Lane2{c0.t, c1.t}, g, a);
  part[0] = crossed_part(x0.b, x0.rho, x0.jd, g[0], a[0]);
  part[1] = crossed_part(x1.b, x1.rho, x1.jd, g[1], a[1]);
}

bool StairAreaMeter::one_pass(const Visit& v, const ArcRec& a, const std::vector<Sub>& subs) {
  if (force_general_ || !v.full || v.sigma != a.dir) return false;
  add_visit(v, static_cast<double>(a.n) * grid_.height, subs);
  return true;
}

void StairAreaMeter::add_sector(SectorIn& in, StairAreaResult& res) {
  const double dr = grid_.height;
  auto& vs = in.vs;
  auto& as = in.as;
  const std::vector<Sub>& subs = *in.subs;
  ++res.sectors;
  if (!in.forced && vs.size() == 1 && as.size() == 1 && one_pass(*vs[0], *as[0], subs)) return;
  bool fast = !force_general_ && !in.forced && !vs.empty() && vs.size() == as.size();
  for (size_t i = 0; fast && i < vs.size(); ++i) fast = vs[i]->full;
  if (fast && vs.size() > 1) {
    // several passes: pair them by height; exact when each pair's range of height is clear of the others
    std::sort(vs.begin(), vs.end(), [](const Visit* x, const Visit* y) { return x->hmin < y->hmin; });
    std::sort(as.begin(), as.end(), [](const ArcRec* x, const ArcRec* y) { return x->n < y->n; });
    double prev_hi = -std::numeric_limits<double>::infinity();
    for (size_t i = 0; fast && i < vs.size(); ++i) {
      const Visit& v = *vs[i];
      const double rho = static_cast<double>(as[i]->n) * dr;
      const double lo = std::min(v.hmin, rho), hi = std::max(v.hmax, rho);
      fast = lo > prev_hi;
      prev_hi = hi;
    }
  }
  for (size_t i = 0; fast && i < vs.size(); ++i) fast = vs[i]->sigma == as[i]->dir;
  if (fast) {
    for (size_t i = 0; i < vs.size(); ++i) add_visit(*vs[i], static_cast<double>(as[i]->n) * dr, subs);
    return;
  }
  ++res.general_sectors;
  std::vector<sweep::Strand>& strands = strands_;
  strands.clear();
  for (const Visit* vp : vs) {
    const Visit& v = *vp;
    for (uint32_t i = v.first; i < v.first + v.count; ++i) {
      const Sub& b = subs[i];
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
  for (const ArcRec* ap : as) {
    sweep::Strand s;
    s.kind = sweep::Strand::level;
    s.sigma = static_cast<int8_t>(-ap->dir);  // the cycle runs the staircase backwards
    s.j = ap->m;
    s.rho = static_cast<double>(ap->n) * dr;
    strands.push_back(s);
  }
  for (const sweep::Strand* e : in.extra) strands.push_back(*e);
  add_total(solver_->area(strands));
}

void StairAreaMeter::set_shift(int64_t g0) {
  const bool polar = grid_.geo == sweep::Geometry::polar;
  const double dth = grid_.width;
  // polar: the angular branch, whole turns that bring the path's start next to the start node
  const double th0 = track_.pieces.front().g_a;
  shift_ = polar ? kTwoPi * std::nearbyint((static_cast<double>(g0) * dth - th0) / kTwoPi) : 0.0;
  frame_ = sweep::Frame{dth, shift_, grid_.geo};
}

void StairAreaMeter::set_range() {
  const sweep::TrackView& tr = track_;
  const bool polar = grid_.geo == sweep::Geometry::polar;
  const double dth = grid_.width;
  const int64_t N = polar ? grid_.steps_per_rev : 0;
  // sectors: the path's abscissa range (plus a margin) in grid units
  const double gmin = (tr.g_min + shift_) / dth, gmax = (tr.g_max + shift_) / dth;
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
}

// ---- the streamed mode

uint64_t StairAreaMeter::key_distance(uint32_t a, uint32_t b) const {
  const uint64_t d = a > b ? a - b : b - a;
  return wrap_ ? std::min<uint64_t>(d, static_cast<uint64_t>(nkeys_) - d) : d;
}

bool StairAreaMeter::pinned(uint32_t k) const {
  if (pin_near_[0] <= k && k <= pin_near_[1]) return pin_near_val_;  // the usual case: beside the last key asked
  // the run of keys about k with k's answer: the interval holding k, or the gap between the intervals about it
  uint32_t lo = 0, hi = std::numeric_limits<uint32_t>::max();
  for (size_t i = 0; i < npin_iv_; ++i) {
    const uint32_t a = pin_iv_[i][0], b = pin_iv_[i][1];
    if (a <= k && k <= b) {
      pin_near_ = pin_iv_[i];
      pin_near_val_ = true;
      return true;
    }
    if (b < k)
      lo = std::max(lo, b + 1);
    else
      hi = std::min(hi, a - 1);
  }
  pin_near_ = {lo, hi};
  pin_near_val_ = false;
  return false;
}

void StairAreaMeter::set_pins() {
  // the keys within the window of each pin (key_distance(k, pin) <= kStreamWindow), as intervals of keys: one a pin,
  // or two where it wraps past the ends of a revolution
  npin_iv_ = 0;
  pin_near_ = {1, 0};  // nothing known
  const int64_t W = kStreamWindow, K = nkeys_;
  for (uint32_t p : pins_) {
    int64_t lo = static_cast<int64_t>(p) - W, hi = static_cast<int64_t>(p) + W;
    if (!wrap_ || 2 * W + 1 >= K) {
      lo = std::max<int64_t>(lo, 0);
      hi = std::min<int64_t>(hi, K - 1);
    } else if (lo < 0) {
      pin_iv_[npin_iv_++] = {static_cast<uint32_t>(lo + K), static_cast<uint32_t>(K - 1)};
      lo = 0;
    } else if (hi >= K) {
      pin_iv_[npin_iv_++] = {0, static_cast<uint32_t>(hi - K)};
      hi = K - 1;
    }
    pin_iv_[npin_iv_++] = {static_cast<uint32_t>(lo), static_cast<uint32_t>(hi)};
  }
}

bool StairAreaMeter::finalized(uint32_t k) const {
  if (k < done_lo_ || k > done_hi_) return false;  // a sector not yet measured beside the last ones (the usual case)
  if (run_lo_ <= k && k <= run_hi_) return true;
  auto it = done_.upper_bound(k);
  if (it == done_.begin()) return false;
  --it;
  return k <= it->second;
}

void StairAreaMeter::mark_finalized(uint32_t k) {
  if (done_lo_ > done_hi_) done_lo_ = done_hi_ = k;
  done_lo_ = std::min(done_lo_, k);
  done_hi_ = std::max(done_hi_, k);
  if (run_lo_ <= run_hi_ && k == run_hi_ + 1) {  // the usual case: the next key of the run
    run_hi_ = k;
    return;
  }
  flush_run();
  run_lo_ = run_hi_ = k;
}

void StairAreaMeter::flush_run() {
  if (run_lo_ > run_hi_) return;
  uint32_t lo = run_lo_, hi = run_hi_;
  run_lo_ = 1, run_hi_ = 0;
  // merged with the ranges it touches or overlaps
  auto next = done_.upper_bound(lo);
  if (next != done_.begin()) {
    auto prev = std::prev(next);
    if (prev->second + 1 >= lo) {
      lo = prev->first;
      hi = std::max(hi, prev->second);
      done_.erase(prev);
    }
  }
  while (next != done_.end() && next->first <= hi + 1) {
    hi = std::max(hi, next->second);
    next = done_.erase(next);
  }
  done_.emplace(lo, hi);
}

StairAreaMeter::Slot* StairAreaMeter::slot(uint32_t k, bool ordered) {
  const uint32_t at = slot_of_.find(k);
  if (at != SlotIndex::kNone) return &slots_[at];
  if (finalized(k)) {
    failed_ = true;  // the staircase or the contour came back to a sector measured already
    return nullptr;
  }
  uint32_t i;
  if (!free_slots_.empty()) {
    i = free_slots_.back();
    free_slots_.pop_back();
  } else {
    i = static_cast<uint32_t>(slots_.size());
    slots_.emplace_back();
  }
  Slot& sl = slots_[i];
  sl.key = k;
  sl.visits.clear();
  sl.subs.clear();
  sl.arcs.clear();
  sl.extra.clear();
  sl.forced = false;
  slot_of_.insert(k, i);
  if (ordered) order_.push_back(pinned(k) ? k | kPinned : k);  // the pins do not move: whether a key is pinned, once
  peak_slots_ = std::max(peak_slots_, slot_of_.size() + pass_n_);
  return &sl;
}

void StairAreaMeter::finalize(uint32_t i) {
  Slot& sl = slots_[i];
  if (!sl.forced && sl.visits.size() == 1 && sl.arcs.size() == 1 && sl.extra.empty() &&
      one_pass(sl.visits[0], sl.arcs[0], sl.subs)) {  // without gathering the sector's strands
    ++sres_.sectors;
    free_slots_.push_back(i);
    return;
  }
  SectorIn& in = sector_in_;
  in.vs.clear();
  in.as.clear();
  in.extra.clear();
  for (size_t v = sl.visits.size(); v-- > 0;) in.vs.push_back(&sl.visits[v]);
  for (size_t a = sl.arcs.size(); a-- > 0;) in.as.push_back(&sl.arcs[a]);
  for (size_t e = sl.extra.size(); e-- > 0;) in.extra.push_back(&sl.extra[e]);
  in.subs = &sl.subs;
  in.forced = sl.forced;
  add_sector(in, sres_);
  free_slots_.push_back(i);
}

void StairAreaMeter::evict(bool all) {
  // in the order the sectors were opened (a slot or an entry of the one-pass queue): the oldest one still within
  // the window of the staircase or the walk keeps every later one
  while (!order_.empty()) {
    // (with the queue on, keys are below kPass, and that bit marks an entry)
    const uint32_t e = order_.front(), k = e & ~(kPinned | (pass_on_ ? kPass : 0u));
    if (!all) {
      if (e & kPinned) {  // near the start or the end: the connectors may add to it
        pinned_.push_back(k);
        order_.pop_front();
        continue;
      }
      if (key_distance(k, stair_key_) <= kStreamWindow) break;
      if (!walk_.done && key_distance(k, walk_key_) <= kStreamWindow) break;
    }
    if (pass_on_ && (e & kPass)) {  // the head of the one-pass queue
      PassEnt& q = pass_[pass_seq0_ & (pass_.size() - 1)];
      ++pass_seq0_;
      --pass_n_;
      if (!q.dead && !force_general_ && q.narcs == 1 && q.arc_dir == q.sigma) {
        // finalize()'s one pass, measured here
        pass_key_[k & (kPassDirect - 1)] = SlotIndex::kNone;
        ++sres_.sectors;
        add_one(q.sub, static_cast<double>(q.arc_n) * grid_.height, q.j);
        order_.pop_front();
        mark_finalized(k);
        continue;
      }
      if (!q.dead) pass_promote(q);  // anything else: measured from the slot it would have been, below
    }
    finalize(slot_of_.find(k));
    slot_of_.erase(k);
    order_.pop_front();
    mark_finalized(k);
  }
  if (all) {
    for (uint32_t k : pinned_) {
      finalize(slot_of_.find(k));
      slot_of_.erase(k);
    }
    pinned_.clear();
  }
}

void StairAreaMeter::begin(int64_t h0, int64_t g0) {
  if (!bound_) throw std::logic_error("StairAreaMeter::begin before reset");
  if (stream_ || nr_ > 0 || nrun_ > 0) throw std::logic_error("StairAreaMeter::begin after the first step");
  set_shift(g0);
  try {
    set_range();
  } catch (const InputError&) {
    return;  // the recorded mode: finish() reports it, in its order
  }
  stream_ = true;
  failed_ = false;
  h0_ = h0;
  g0_ = g0;
  solver_ = std::make_unique<sweep::SectorSolver>(track_, areas_, frame_);
  total_ = Neumaier{};
  pending_.clear();
  crossings_.clear();
  sres_ = StairAreaResult{};
  const double dth = grid_.width;
  auto key_near = [&](double g) {
    const int64_t j = std::clamp(static_cast<int64_t>(std::floor(g)), j_lo_, j_hi_);
    return key(j);
  };
  const auto& P = track_.pieces;
  pins_[0] = key_near(static_cast<double>(g0));
  pins_[1] = key_near((P.front().g_a + shift_) / dth);
  pins_[2] = key_near((P.back().g_b + shift_) / dth);
  set_pins();
  stair_key_ = walk_key_ = pins_[0];
  open_ = -1;
  pass_clear();
  pass_on_ = !force_general_ && nkeys_ <= int64_t{kPass};  // keys below kPass: order_ can mark an entry by that bit
  walk_start();
}

void StairAreaMeter::stream_run(int dir) {
  if (failed_) return;
  const int64_t n = h0_ + n_, mb = g0_ + m_;
  const int64_t j = dir > 0 ? mb : mb - 1;  // the sector the level strand spans
  if (j < j_lo_ || j > j_hi_) {
    const bool polar = grid_.geo == sweep::Geometry::polar;
    const std::string node = polar ? "(" + std::to_string(n) + ", " + std::to_string(mb) + ")"
                                   : "(" + std::to_string(mb) + ", " + std::to_string(n) + ")";
    range_error_ = std::string(polar ? "the" : "the Cartesian") + " tape does not follow this path: its " +
                   std::string(polar ? "angular" : "x") + " step " + std::to_string(nrun_ + 1) + " leaves the path's " +
                   (polar ? "angular" : "x") + " range (node " + node + ")";
    failed_ = true;
    return;
  }
  const uint32_t k = key(j);
  PassEnt* e = pass_on_ ? pass_find(k) : nullptr;
  if (e && e->narcs == 0) {  // the usual case: the sector's one level strand
    e->narcs = 1;
    e->arc_n = n;
    e->arc_dir = static_cast<int8_t>(dir);
  } else {
    Slot* sl = stream_slot(k);
    if (!sl) return;
    sl->arcs.push_back({n, j, -1, static_cast<int8_t>(dir)});
  }
  stair_key_ = k;
  // keep the contour's walk up with the staircase: about as many sectors walked as level strands stepped
  while (!failed_ && !walk_.done && subs_out_ < nrun_ + 1 + kStreamWindow / 2) walk_next();
  // the sectors left behind, every 16 level strands (a sector measured later than it could be is measured the same)
  if (!failed_ && (nrun_ & 15) == 0) evict(false);
}

// ---- the streamed mode's one-pass queue

void StairAreaMeter::pass_clear() {
  pass_seq0_ = 0;
  pass_n_ = 0;
  pass_key_.fill(SlotIndex::kNone);
}

StairAreaMeter::PassEnt* StairAreaMeter::pass_find(uint32_t k) {
  const uint32_t d = k & (kPassDirect - 1);
  if (pass_key_[d] != k) return nullptr;
  return &pass_[pass_seq_[d] & (pass_.size() - 1)];
}

bool StairAreaMeter::pass_sub(const Sub& s, int64_t j, int8_t sg, uint32_t k) {
  // a sub from ray to ray of a sector with no strand yet, away from the pins, whose cell of the index is free
  const uint32_t d = k & (kPassDirect - 1);
  if (!(std::abs(s.l1 - s.l0) == 1.0) || pass_key_[d] != SlotIndex::kNone || slot_of_.find(k) != SlotIndex::kNone ||
      finalized(k) || pinned(k))
    return false;
  if (open_ >= 0) close_visit();
  if (pass_n_ == pass_.size()) {  // grow: each entry to its place in a ring twice the size
    std::vector<PassEnt> b(std::max<size_t>(256, 2 * pass_.size()));
    for (uint64_t q = pass_seq0_; q < pass_seq0_ + pass_n_; ++q) b[q & (b.size() - 1)] = pass_[q & (pass_.size() - 1)];
    pass_ = std::move(b);
  }
  const uint64_t q = pass_seq0_ + pass_n_;
  pass_[q & (pass_.size() - 1)] = PassEnt{s, j, 0, k, sg, 0, 0, false};
  ++pass_n_;
  pass_key_[d] = k;
  pass_seq_[d] = q;
  order_.push_back(k | kPass);
  peak_slots_ = std::max(peak_slots_, slot_of_.size() + pass_n_);
  return true;
}

void StairAreaMeter::pass_promote(PassEnt& e) {
  // the slot the entry would have been: its visit (closed: one sub, from ray to ray) and its level strand; it keeps
  // the entry's place in the order of measurement
  e.dead = true;
  pass_key_[e.key & (kPassDirect - 1)] = SlotIndex::kNone;
  Slot* sl = slot(e.key, false);
  if (!sl) return;
  const double lo = std::min(e.sub.h0, e.sub.h1), hi = std::max(e.sub.h0, e.sub.h1);
  sl->visits.push_back(Visit{e.j, static_cast<uint32_t>(sl->subs.size()), 1, -1, e.sigma, true, lo, hi});
  sl->subs.push_back(e.sub);
  if (e.narcs == 1) sl->arcs.push_back({e.arc_n, e.j, -1, e.arc_dir});
}

StairAreaMeter::Slot* StairAreaMeter::stream_slot(uint32_t k) {
  if (pass_on_)
    if (PassEnt* e = pass_find(k)) pass_promote(*e);
  return slot(k);
}

StairAreaResult StairAreaMeter::finish(int64_t n0, int64_t m0) {
  if (!bound_) throw std::logic_error("StairAreaMeter::finish before reset");
  if (stream_ && (n0 != h0_ || m0 != g0_)) throw std::logic_error("StairAreaMeter::finish: not the node given to begin()");
  const sweep::TrackView& tr = track_;
  const auto& P = tr.pieces;
  const bool polar = grid_.geo == sweep::Geometry::polar;
  const double dr = grid_.height, dth = grid_.width;
  const int64_t N = polar ? grid_.steps_per_rev : 0;

  StairAreaResult res;
  res.rise_steps = nr_;
  res.run_steps = nrun_;
  set_shift(m0);
  const double shift = shift_;
  res.shift = shift;

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

  // connectors close the cycle unless both the path and the staircase close on themselves
  const bool closes = tr.closed && n_ == 0 &&
                      (N > 0 ? m_ == static_cast<int64_t>(tr.winding) * N : (m_ == 0 && tr.winding == 0));
  auto connect = [&] {
    if (closes) return;
    // straight segments from the staircase's start node to the path's start, and from the path's end to the
    // staircase's end node
    add_connector(node_point(n0, m0), static_cast<double>(m0), path_point(P.front().h_a, P.front().g_a),
                  (P.front().g_a + shift) / dth);
    add_connector(path_point(P.back().h_b, P.back().g_b), (P.back().g_b + shift) / dth, node_point(n1, m1),
                  static_cast<double>(m1));
  };

  if (stream_) {
    if (!range_error_.empty()) throw InputError(range_error_);
    while (!failed_ && walk_next()) {
    }
    if (!failed_) connect();
    if (!failed_) evict(true);
    stream_ = false;
    n_ = m_ = 0;
    nr_ = nrun_ = 0;
    if (failed_) return res;  // streamed() is false: the caller replays the steps into a recording meter
    res.sectors = sres_.sectors;
    res.general_sectors = sres_.general_sectors;
    flush_pending();
    res.area_m2 = total_.value();
    if (!std::isfinite(res.area_m2)) throw std::logic_error("internal error: the area error is not finite");
    return res;
  }

  // the contour's visits were made already where imply_nearest() made the staircase
  const bool walked = imp_.walked;
  imp_.walked = false;
  if (!walked) prepare_recorded();
  const size_t nk = static_cast<size_t>(nkeys_);

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

  if (!walked) {
    walk_start();
    while (walk_next()) {
    }
  }
  connect();

  solver_ = std::make_unique<sweep::SectorSolver>(tr, areas_, frame_);
  total_ = Neumaier{};
  pending_.clear();
  crossings_.clear();
  SectorIn& in = sector_in_;
  in.subs = &subs_;
  const bool dense = !imp_.part.empty();
  const double* const dpart = imp_.part.data();
  for (size_t k = 0; k < nk; ++k) {
    if (dense && !std::isnan(dpart[k])) {
      // measured by the walk (imply_nearest): the sector's only visit and level strand. A run of such sectors is
      // added as add_total would add them one by one (nothing waits: the crossings before are measured first),
      // in a local sum the compiler can keep in registers (total_ may alias the parts' doubles)
      flush_pending();
      size_t e = k;
      while (e < nk && !std::isnan(dpart[e])) ++e;
      // none of the run's sectors has another strand: no head is set (each is -1, or a strand's index, >= 0)
      int32_t others = 0;
      for (size_t i = k; i < e; ++i) others |= ~visit_head_[i] | ~arc_head_[i] | ~extra_head_[i];
      if (others < 0) throw std::logic_error("internal error: a sector measured by the walk has other strands");
      Neumaier sum = total_;
      for (size_t i = k; i < e; ++i) sum.add(dpart[i]);
      total_ = sum;
      res.sectors += e - k;
      k = e - 1;  // the loop's increment steps onto the key that ended the run
      continue;
    }
    if (visit_head_[k] < 0 && arc_head_[k] < 0 && extra_head_[k] < 0) continue;
    in.vs.clear();
    in.as.clear();
    in.extra.clear();
    for (int32_t v = visit_head_[k]; v >= 0; v = visits_[static_cast<size_t>(v)].next) in.vs.push_back(&visits_[static_cast<size_t>(v)]);
    for (int32_t a = arc_head_[k]; a >= 0; a = arcs_[static_cast<size_t>(a)].next) in.as.push_back(&arcs_[static_cast<size_t>(a)]);
    for (int32_t e = extra_head_[k]; e >= 0; e = extra_next_[static_cast<size_t>(e)]) in.extra.push_back(&extra_[static_cast<size_t>(e)]);
    in.forced = forced_[k] != 0;
    add_sector(in, res);
  }
  flush_pending();
  imp_.part.clear();
  res.area_m2 = total_.value();
  if (!std::isfinite(res.area_m2)) throw std::logic_error("internal error: the area error is not finite");
  // the recorded steps are now absolute; the meter must be reset before it is used again
  arcs_.clear();
  n_ = m_ = 0;
  nr_ = nrun_ = 0;
  return res;
}

int StairAreaMeter::path_direction() const {
  // the angle at every segment's ends: each segment must move it the same way, and the path must not cover a sector
  // twice (a closed path once round the pole covers its start's sector twice, partly each time: not a full visit)
  const auto& P = track_.pieces;
  const auto& E = *track_.extrema;
  if (P.empty()) return 0;
  int dir = 0;
  for (const sweep::PieceView& p : P) {
    double prev = p.g_a;
    for (uint32_t k = p.ext_begin; k <= p.ext_end; ++k) {
      const double g = k < p.ext_end ? p.g_a + (*p.G)(E[k]) : p.g_b;
      const int d = g > prev ? 1 : (g < prev ? -1 : 0);
      if (d == 0 || (dir != 0 && d != dir)) return 0;
      dir = d;
      prev = g;
    }
  }
  const double w = grid_.width, span = std::abs(P.back().g_b - P.front().g_a) / w;
  const int64_t N = grid_.steps_per_rev;
  if (N > 0 && !(span <= static_cast<double>(N) - 2.0)) {
    const double g0 = (P.front().g_a + shift_) / w, d = g0 - std::floor(g0);
    if (!(track_.closed && std::abs(track_.winding) == 1 && d > 1e-6 && d < 1.0 - 1e-6 &&
          span <= static_cast<double>(N) + 1e-6))
      return 0;
  }
  return dir;
}

void StairAreaMeter::dense_sub(const Sub& s, int64_t j, int8_t sg, double lo, double hi) {
  Implied& im = imp_;
  if (im.open && im.j == j) {
    if (im.sigma != sg) im.sigma = 0;
    if (lo < im.hmin) im.hmin = lo;
    if (hi > im.hmax) im.hmax = hi;
    im.subs.push_back(s);
    return;
  }
  dense_close();
  im.open = true;
  im.j = j;
  im.sigma = sg;
  im.hmin = lo;
  im.hmax = hi;
  im.subs.clear();
  im.subs.push_back(s);
}

void StairAreaMeter::dense_close() {
  Implied& im = imp_;
  if (!im.open) return;
  im.open = false;
  dense_visit(im.subs.data(), im.subs.size(), im.j, im.sigma, im.hmin, im.hmax);
}

void StairAreaMeter::dense_visit(const Sub* subs, size_t count, int64_t j, int8_t sigma, double hmin, double hmax) {
  Implied& im = imp_;
  // this sector's level strands: at the front of the queue (the strands of the sectors before were taken by their
  // visits; a strand of a sector behind this one would mean the walk and the strands disagree)
  size_t a0 = im.head, a1 = a0;
  while (a1 < im.arcs.size() && im.arcs[a1].j == j) ++a1;
  if (a1 == a0 && a0 < im.arcs.size() && (im.arcs[a0].j - j) * im.dir < 0) im.failed = true;
  im.head = a1;
  if (full_visit(sigma, subs[0], subs[count - 1]) && a1 - a0 == 1 && im.arcs[a0].dir == sigma) {
    dense_part(subs, count, im.arcs[a0], j);
    return;
  }
  // anything else goes to the lists, as add_sub and run() would have put it
  open_ = static_cast<int>(visits_.size());
  visits_.push_back(Visit{j, static_cast<uint32_t>(subs_.size()), static_cast<uint32_t>(count), -1, sigma, false,
                          hmin, hmax});
  subs_.insert(subs_.end(), subs, subs + count);
  close_visit();
  for (size_t i = a0; i < a1; ++i) arcs_.push_back({im.arcs[i].n, im.arcs[i].m, -1, im.arcs[i].dir});
}

void StairAreaMeter::dense_part(const Sub* subs, size_t count, const Implied::Arc& arc, int64_t j) {
  // the sector's only visit and only level strand: add_sector's one_pass (add_visit), measured now
  const double rho = static_cast<double>(arc.n + imp_.h0) * grid_.height;
  const double jd = static_cast<double>(j);
  const uint32_t k = key(j);
  if (count == 1 && crosses(subs[0].h0, subs[0].h1, rho))
    dense_crossing(subs[0], rho, jd, k);
  else
    imp_.part[k] = count == 1 ? sub_part(subs[0], rho, jd) : fast_visit(subs, count, rho, jd);
}

void StairAreaMeter::dense_crossing(const Sub& b, double rho, double jd, uint32_t k) {
  dense_x_[dense_n_++] = Crossing{b, rho, jd, k};
  if (dense_n_ == crossing_batch()) dense_flush();
}

void StairAreaMeter::crossing_quad(const Crossing* x, double part[4]) {
  const auto& P = track_.pieces;
  bool same = true;
  for (int q = 0; q < 4; ++q) same = same && x[q].b.piece == quad_[q];
  if (!same) {
    const Cheb* H[4];
    const Cheb* G[4];
    const LongCheb* A[4];
    for (int q = 0; q < 4; ++q) {
      const uint32_t i = x[q].b.piece;
      H[q] = P[i].H, G[q] = P[i].G, A[q] = &areas_[i];
      quad_[q] = i;
    }
    area_roots::prepare_quad(quad_series_, H, G, A);
  }
  RadiusCrossing c[4];
  for (int q = 0; q < 4; ++q) start_crossing(x[q].b, x[q].rho, c[q]);
  double g[4], a[4];
  area_roots::radius_crossing4(quad_series_, c, g, a);
  for (int q = 0; q < 4; ++q) part[q] = crossed_part(x[q].b, x[q].rho, x[q].jd, g[q], a[q]);
}

void StairAreaMeter::dense_flush() {
  double part[4] = {0.0, 0.0, 0.0, 0.0};
  crossing_parts(dense_x_, dense_n_, part);
  for (size_t i = 0; i < dense_n_; ++i) imp_.part[dense_x_[i].key] = part[i];
  dense_n_ = 0;
}

void StairAreaMeter::prepare_recorded() {
  set_range();
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
