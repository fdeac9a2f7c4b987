#pragma once
// The one step walker: every step of a two-axis machine, in order, at the arc length where the path meets the
// step's level, for any kinematics whose axis track (axis_track.hpp) has been built.
//
// Each axis a is a quantiser of the continuous coordinate f_a = (q_a + offset_a) / res_a with threshold h: from
// node v it steps up when f reaches v + h and down when f falls below v - h (h = 1/2: the nearest node always;
// h = 1: the thesis rule). Between consecutive extrema of a piece both coordinates are monotone, so each axis's
// crossings there come in order; each is found by the level-crossing solver (level_crossing.hpp) from a guess
// extrapolated from the axis's previous crossings. The two axes' crossings are merged by t; at equal t axis 0
// comes first.
//
// The walker is a template on its style and its emitter, so the inner loop has no indirect calls: the polar
// digitizer (digitize.cpp), the theta-rho digitizer and the exact Cartesian generator
// (machine/cartesian/cartesian_exact.cpp) are instances of it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "digitizer/axis_track.hpp"
#include "digitizer/level_crossing.hpp"
#include "digitizer/level_inverse.hpp"

namespace polarcam {

// How the track's coordinates meet the grid of steps.
struct WalkGrid {
  double res[2] = {1, 1};     // coordinate per step of each axis
  double offset[2] = {0, 0};  // added to the coordinate before quantising (a whole-turn shift of an angle)
  double h = 0.5;             // threshold: 1/2 (nearest node) or 1 (thesis)
  // The end of the path in steps when it is known exactly (a closed path's angle after whole turns), else NaN.
  double last_end[2] = {NAN, NAN};
};

// kArcInSolver: the solver carries S(t) through its iterations (cheap when most crossings are emitted at once);
// otherwise S is evaluated once a step. kHistory: crossings the starting guess is extrapolated from (2: linear,
// 3: quadratic).
template <bool kArcInSolver, int kHistory>
struct WalkStyle {
  static constexpr bool arc_in_solver = kArcInSolver;
  static constexpr int history = kHistory;
};

// The steps of both axes on one monotone sub-interval [tl, th] of a piece, in order, with the arc length from the
// solver (the digitizer's style). Each axis's crossings depend only on that axis (its level, its bracket from its
// previous crossing, its guess from its earlier crossings), so the two axes are solved side by side: while both
// have a crossing to find, one eval_gs2 serves an iteration of each (two independent chains of dependent
// arithmetic run in the time of about one). Each axis finds up to kAhead crossings ahead of the steps emitted;
// between iterations the crossings whose turn has come are emitted, in order of t (axis 0 first at equal t), so
// the emitter's work fills the time the solver waits on its own arithmetic. Every point, value and result is that
// of solving the crossings one at a time with solve_crossing<true>: the steps, arc lengths and so the times are
// bit for bit the same, and so is the order of the emitter's calls.
template <class Emit>
void walk_sub_interval(const Lane2 packed[2][kChebMaxDegree + 1], const int n_axis[2], const double bound[3],
                       const Lane2* coef_g, const Lane2* coef_s, const TrackPiece& pc,
                       const double base[2], const double fprev[2], const double fend[2], double tl, double th,
                       double h, int64_t node[2], Emit& emit) {
  constexpr unsigned kAhead = 64;  // a power of two: the crossings waiting are a ring
  struct Axis {
    int dir = 0;
    bool done = false, solving = false;
    double lo = 0, flo = 0, level = 0;  // bracket start (the last crossing) and the axis value there
    RootHistory hist;
    CrossingSolve q;
    unsigned head = 0, tail = 0;  // crossings found and not yet emitted: [head, tail) modulo kAhead
    double bt[kAhead], bs[kAhead];
  };
  Axis ax[2];
  const int n01 = std::max(n_axis[0], n_axis[1]);
  auto record = [&](int a) {
    Axis& x = ax[a];
    x.solving = false;
    x.bt[x.tail % kAhead] = x.q.r.t;
    x.bs[x.tail % kAhead] = x.q.r.s;
    ++x.tail;
    node[a] += x.dir;
    x.lo = x.q.r.t;
    x.flo = x.level;  // the axis stands at the level it just crossed
    x.hist.push(x.q.r.t);
  };
  // Starts the axis's next crossing while it has one and room for it; crossings known without iterating are recorded.
  auto begin = [&](int a) {
    Axis& x = ax[a];
    while (!x.done && !x.solving && x.tail - x.head < kAhead) {
      const double level = static_cast<double>(node[a]) + (x.dir > 0 ? h : -h);
      if (x.dir == 0 || (x.dir > 0 ? !(fend[a] >= level) : !(fend[a] < level))) {
        x.done = true;
        return;
      }
      const double guess = x.hist.guess(-2.0);  // -2: none, the solver starts from the secant
      x.level = level;
      if (x.q.start(pc.S, level - base[a], x.lo, th, x.flo - level, fend[a] - level, guess))
        x.solving = true;
      else
        record(a);
    }
  };
  // Emits the crossings whose turn has come: the earlier of the two axes' next ones, while each axis has its next
  // one found or has none left.
  auto emit_ready = [&] {
    for (;;) {
      const bool h0 = ax[0].head != ax[0].tail, h1 = ax[1].head != ax[1].tail;
      if ((!h0 && !ax[0].done) || (!h1 && !ax[1].done) || (!h0 && !h1)) return;
      const int a = (h0 && (!h1 || ax[0].bt[ax[0].head % kAhead] <= ax[1].bt[ax[1].head % kAhead])) ? 0 : 1;
      Axis& x = ax[a];
      emit(a, x.dir, pc.s0 + x.bs[x.head % kAhead]);
      ++x.head;
    }
  };
  // the second derivatives at an axis's point, as eval_gs computes them, when the bounds do not decide
  auto second = [&](int a) {
    return [&, a] {
      const GS v = eval_gs_packed<true>(packed[a], n_axis[a], ax[a].q.t);
      return std::pair<double, double>{v.g2, v.s2};
    };
  };
  for (int a = 0; a < 2; ++a) {
    ax[a].dir = fend[a] > fprev[a] ? 1 : (fend[a] < fprev[a] ? -1 : 0);
    ax[a].lo = tl;
    ax[a].flo = fprev[a];
  }
  for (;;) {
    begin(0);
    begin(1);
    if (ax[0].solving && ax[1].solving) {
      const GS2 v = eval_gs2<false>(coef_g, coef_s, n01, Lane2{ax[0].q.t, ax[1].q.t});
      for (int a = 0; a < 2; ++a)
        if (ax[a].q.next_lazy(pc.S, v.g[a], v.g1[a], v.s[a], v.s1[a], bound[a], bound[2], second(a))) record(a);
    } else if (ax[0].solving || ax[1].solving) {
      const int a = ax[0].solving ? 0 : 1;
      const GS v = eval_gs_packed<false>(packed[a], n_axis[a], ax[a].q.t);
      if (ax[a].q.next_lazy(pc.S, v.g, v.g1, v.s, v.s1, bound[a], bound[2], second(a))) record(a);
    }
    emit_ready();
    if (ax[0].done && ax[1].done && ax[0].head == ax[0].tail && ax[1].head == ax[1].tail) return;
  }
}

// The steps of both axes on one monotone sub-interval [tl, th] of a piece by the inverse (level_inverse.hpp): each
// axis's levels are counted, the sub-interval is cut in halves until each part either carries a certified fit of
// the arc length as a polynomial of the level (then every level of the part is one evaluation) or has fewer than
// kMinFitLevels levels (then they are solved one by one from extrapolated guesses, solve_crossing, as before). The
// arc lengths of the two axes are merged in order; where two are within 4 tol of each other (their order not
// certain) both crossings are solved and ordered by t, axis 0 first at equal t, as walk_sub_interval orders them.
// Every arc length is within tol of the exact one (to the rounding of the series), so a step's time moves by
// less than tol over the speed; the steps, their axes, directions and order are those of walk_sub_interval.
struct InverseScratch {
  std::vector<double> s[2];
  LevelInverse inv;
  // what the inverse did on this thread (for tests and measurements): levels timed by a fit and one by one, fits
  // accepted and refused, near-ties ordered by solving, sub-intervals walked in halves for their number of levels
  uint64_t fitted_levels = 0, solved_levels = 0, fits = 0, refused = 0, ties = 0, halves = 0;
};
inline InverseScratch& inverse_scratch() {
  static thread_local InverseScratch s;
  return s;
}
// When neither axis has kMinFitLevels levels on the sub-interval, walk_sub_interval walks it
// (legacy(fprev, fend, tl, th)). A sub-interval with more than kMaxLevels levels is walked in halves (of t), so that
// the arc lengths held at once stay bounded however fine the grid: the walk streams in constant memory.
template <class Emit, class Legacy>
void walk_sub_interval_inverse(const Cheb g[2], const Lane2 packed[2][kChebMaxDegree + 1], const int n_axis[2],
                               const TrackPiece& pc, const double base[2], const double fprev[2],
                               const double fend[2], double tl, double th, double h, int64_t node[2], double tol,
                               InverseScratch& scr, Emit& emit, Legacy&& legacy) {
  constexpr size_t kMinFitLevels = 32, kMaxLevels = size_t{1} << 14;
  int dir[2];
  size_t m[2];
  auto level = [&](int a, size_t j) {
    return static_cast<double>(node[a] + dir[a] * static_cast<int64_t>(j)) + (dir[a] > 0 ? h : -h);
  };
  auto reached = [&](int a, double f, double lv) { return dir[a] > 0 ? f >= lv : f < lv; };
  for (int a = 0; a < 2; ++a) {
    dir[a] = fend[a] > fprev[a] ? 1 : (fend[a] < fprev[a] ? -1 : 0);
    m[a] = 0;
    if (dir[a] == 0) continue;
    // the levels reached by fend: an estimate, then the exact test at its edge
    const double est = dir[a] > 0 ? std::floor(fend[a] - h - static_cast<double>(node[a]))
                                  : std::floor(static_cast<double>(node[a]) - h - fend[a]);
    size_t k = est > 0 ? static_cast<size_t>(est) : 0;
    while (k > 0 && !reached(a, fend[a], level(a, k - 1))) --k;
    while (reached(a, fend[a], level(a, k))) ++k;
    m[a] = k;
  }
  if (m[0] < kMinFitLevels && m[1] < kMinFitLevels) {
    scr.solved_levels += m[0] + m[1];
    legacy(fprev, fend, tl, th);
    return;
  }
  if (m[0] + m[1] > kMaxLevels) {
    // the axis values at the middle, kept between those at the ends (an axis that does not move stays put), so
    // that the two halves' levels are exactly this sub-interval's, in order
    const double tm = 0.5 * (tl + th);
    double fm[2];
    for (int a = 0; a < 2; ++a) {
      fm[a] = fprev[a];
      if (dir[a] != 0)
        fm[a] = std::clamp(base[a] + g[a](tm), std::min(fprev[a], fend[a]), std::max(fprev[a], fend[a]));
    }
    if (tm > tl && tm < th) {
      ++scr.halves;
      walk_sub_interval_inverse(g, packed, n_axis, pc, base, fprev, fm, tl, tm, h, node, tol, scr, emit, legacy);
      walk_sub_interval_inverse(g, packed, n_axis, pc, base, fm, fend, tm, th, h, node, tol, scr, emit, legacy);
      return;
    }
  }
  // The crossings of levels [j0, j1) of axis a on [ta, tb], fa and fb the axis values at the ends.
  auto one_by_one = [&](int a, double ta, double tb, double fa, double fb, size_t j0, size_t j1) {
    double lo = ta, flo = fa;
    RootHistory hist;
    for (size_t j = j0; j < j1; ++j) {
      const double lv = level(a, j);
      const LevelCrossing r =
          solve_crossing<true>(g[a], pc.S, lv - base[a], lo, tb, flo - lv, fb - lv, hist.guess(-2.0));
      scr.s[a][j] = r.s;
      lo = r.t;
      flo = lv;
      hist.push(r.t);
    }
  };
  auto fill = [&](auto&& self, int a, double ta, double tb, double fa, double fb, size_t j0, size_t j1,
                  int depth) -> void {
    if (j1 == j0) return;
    if (j1 - j0 >= kMinFitLevels) {
      LevelInverse& inv = scr.inv;
      if (fit_level_inverse(packed[a], n_axis[a], ta, tb, tol, inv)) {
        ++scr.fits;
        scr.fitted_levels += j1 - j0;
        eval_levels(inv, static_cast<double>(node[a] + dir[a] * static_cast<int64_t>(j0)), dir[a],
                    dir[a] > 0 ? h : -h, base[a], j1 - j0, scr.s[a].data() + j0);
        return;
      }
      ++scr.refused;
      if (depth < 40) {
        const double tm = 0.5 * (ta + tb), fm = base[a] + g[a](tm);
        size_t jm = j0;
        while (jm < j1 && reached(a, fm, level(a, jm))) ++jm;
        self(self, a, ta, tm, fa, fm, j0, jm, depth + 1);
        self(self, a, tm, tb, fm, fb, jm, j1, depth + 1);
        return;
      }
    }
    scr.solved_levels += j1 - j0;
    one_by_one(a, ta, tb, fa, fb, j0, j1);
  };
  for (int a = 0; a < 2; ++a) {
    if (scr.s[a].size() < m[a]) scr.s[a].resize(m[a]);
    fill(fill, a, tl, th, fprev[a], fend[a], 0, m[a], 0);
  }
  // merge by arc length
  const double* s0 = scr.s[0].data();
  const double* s1 = scr.s[1].data();
  size_t i0 = 0, i1 = 0;
  const double tie = 4.0 * tol;
  auto exact_t = [&](int a, size_t j) {
    const double lv = level(a, j);
    return solve_crossing<false>(g[a], pc.S, lv - base[a], tl, th, fprev[a] - lv, fend[a] - lv, -2.0).t;
  };
  while (i0 < m[0] && i1 < m[1]) {
    int a = s0[i0] <= s1[i1] ? 0 : 1;
    if (std::abs(s0[i0] - s1[i1]) <= tie) {
      ++scr.ties;
      a = exact_t(0, i0) <= exact_t(1, i1) ? 0 : 1;
    }
    if (a == 0) {
      emit(0, dir[0], pc.s0 + s0[i0]);
      ++i0;
    } else {
      emit(1, dir[1], pc.s0 + s1[i1]);
      ++i1;
    }
  }
  for (; i0 < m[0]; ++i0) emit(0, dir[0], pc.s0 + s0[i0]);
  for (; i1 < m[1]; ++i1) emit(1, dir[1], pc.s0 + s1[i1]);
  for (int a = 0; a < 2; ++a) node[a] += dir[a] * static_cast<int64_t>(m[a]);
}

// Walks one piece of a track from the nodes in `node` (updated to the nodes at its end): `ext` its `n_ext` interior
// extrema (sorted t in (-1, 1)), `closing` when it is the last piece of a closed path (its end is then
// wg.last_end where that is known). With kEmit, emit(axis, dir, s) is called for every step, s the arc length
// from the path start; without it only the nodes are tracked (no root finding). `ts` is scratch space.
// Pieces walked one after the other give the same steps as walk_steps over a track holding them all, so a
// track whose pieces are made as they are walked (digitizer/theta_rho.hpp, PolylineTrack) needs no more memory
// than one piece.
template <bool kEmit, class Style, class Emit>
void walk_piece(const TrackPiece& pc, const double* ext, size_t n_ext, bool closing, const WalkGrid& wg,
                int64_t node[2], Emit& emit, std::vector<double>& ts) {
  struct Cursor {
    int dir = 0;
    bool has = false;
    double level = 0, t = 0, s = 0;  // pending crossing
    double lo = 0, flo = 0;          // bracket start and the axis value there (minus the level when solving)
    double hist[3] = {0, 0, 0};      // the axis's last crossings on this sub-interval, newest first
    int nh = 0;
  };
  const double h = wg.h;
  Cheb g[2];
  {
    double base[2], end[2];
    for (int a = 0; a < 2; ++a) {
      g[a] = pc.Q[a];
      g[a].scale(1.0 / wg.res[a]);
      base[a] = (pc.q_a[a] + wg.offset[a]) / wg.res[a];
      end[a] = (pc.q_b[a] + wg.offset[a]) / wg.res[a];
      if (closing && !std::isnan(wg.last_end[a])) end[a] = wg.last_end[a];
    }
    // both axes' series on the two lanes of eval_gs2, zero above each axis's own degree (see there)
    // and each axis's series with the arc length's on the two lanes of eval_gs_packed
    Lane2 coef_g[kChebMaxDegree + 1], coef_s[kChebMaxDegree + 1], packed[2][kChebMaxDegree + 1];
    const int n_axis[2] = {std::max(g[0].deg, pc.S.deg), std::max(g[1].deg, pc.S.deg)};
    if constexpr (kEmit && Style::arc_in_solver) {
      for (int k = 0; k <= kChebMaxDegree; ++k) {
        coef_g[k] = Lane2{k <= n_axis[0] ? g[0].c[k] : 0.0, k <= n_axis[1] ? g[1].c[k] : 0.0};
        coef_s[k] = Lane2{k <= n_axis[0] ? pc.S.c[k] : 0.0, k <= n_axis[1] ? pc.S.c[k] : 0.0};
        for (int a = 0; a < 2; ++a) packed[a][k] = Lane2{g[a].c[k], pc.S.c[k]};
      }
    }
    // bounds on |g_0''|, |g_1''| and |S''| (second_derivative_bound) over the series as evaluated
    const double bound[3] = {second_derivative_bound(g[0].c.data(), n_axis[0]),
                             second_derivative_bound(g[1].c.data(), n_axis[1]),
                             second_derivative_bound(pc.S.c.data(), std::max(n_axis[0], n_axis[1]))};
    // the inverse (walk_sub_interval_inverse) where the emitter says how far an arc length may be off
    double arc_tol = 0.0;
    if constexpr (kEmit && Style::arc_in_solver && requires { emit.arc_tolerance(0.0, 0.0); })
      arc_tol = emit.arc_tolerance(pc.s0, pc.s0 + pc.len);
    InverseScratch& inv_scratch = inverse_scratch();
    ts.assign(1, -1.0);
    for (size_t k = 0; k < n_ext; ++k) ts.push_back(ext[k]);
    ts.push_back(1.0);
    double fprev[2] = {base[0], base[1]};
    for (size_t k = 0; k + 1 < ts.size(); ++k) {
      const double tl = ts[k], th = ts[k + 1];
      double fend[2];
      for (int a = 0; a < 2; ++a) fend[a] = (k + 2 == ts.size()) ? end[a] : base[a] + g[a](th);
      if constexpr (!kEmit) {
        for (int a = 0; a < 2; ++a) {
          if (fend[a] > fprev[a]) {
            const double v = std::floor(fend[a] - h) + 1.0;
            if (v > static_cast<double>(node[a])) node[a] = static_cast<int64_t>(v);
          } else if (fend[a] < fprev[a]) {
            const double v = std::floor(fend[a] + h);
            if (v < static_cast<double>(node[a])) node[a] = static_cast<int64_t>(v);
          }
        }
      } else if constexpr (Style::arc_in_solver) {
        auto legacy = [&](const double* fp, const double* fe, double ta, double tb) {
          walk_sub_interval(packed, n_axis, bound, coef_g, coef_s, pc, base, fp, fe, ta, tb, h, node, emit);
        };
        if (arc_tol > 0.0)
          walk_sub_interval_inverse(g, packed, n_axis, pc, base, fprev, fend, tl, th, h, node, arc_tol, inv_scratch,
                                    emit, legacy);
        else
          legacy(fprev, fend, tl, th);
      } else {
        Cursor cur[2];
        auto advance = [&](int a) {
          Cursor& c = cur[a];
          c.has = false;
          if (c.dir == 0) return;
          const double level = static_cast<double>(node[a]) + (c.dir > 0 ? h : -h);
          if (c.dir > 0 ? !(fend[a] >= level) : !(fend[a] < level)) return;
          double guess = -2.0;  // none: the solver starts from the secant
          if (Style::history >= 3 && c.nh >= 3)
            guess = 3.0 * c.hist[0] - 3.0 * c.hist[1] + c.hist[2];
          else if (c.nh >= 2)
            guess = 2.0 * c.hist[0] - c.hist[1];
          const LevelCrossing r = solve_crossing<Style::arc_in_solver>(g[a], pc.S, level - base[a], c.lo, th,
                                                                       c.flo - level, fend[a] - level, guess);
          c.has = true;
          c.level = level;
          c.t = r.t;
          c.s = r.s;
        };
        for (int a = 0; a < 2; ++a) {
          cur[a].dir = fend[a] > fprev[a] ? 1 : (fend[a] < fprev[a] ? -1 : 0);
          cur[a].lo = tl;
          cur[a].flo = fprev[a];
          advance(a);
        }
        while (cur[0].has || cur[1].has) {
          const int a = (cur[0].has && (!cur[1].has || cur[0].t <= cur[1].t)) ? 0 : 1;
          Cursor& c = cur[a];
          emit(a, c.dir, pc.s0 + (Style::arc_in_solver ? c.s : pc.S(c.t)));
          node[a] += c.dir;
          c.lo = c.t;
          c.flo = c.level;  // the axis stands at the level it just crossed
          for (int j = Style::history - 1; j > 0; --j) c.hist[j] = c.hist[j - 1];
          c.hist[0] = c.t;
          if (c.nh < Style::history) ++c.nh;
          advance(a);
        }
      }
      fprev[0] = fend[0];
      fprev[1] = fend[1];
    }
  }
}

// Walks the whole track from the nodes in `node` (updated to the end nodes), piece by piece (walk_piece).
template <bool kEmit, class Style, class Emit>
void walk_steps(const AxisTrack& tr, const WalkGrid& wg, int64_t node[2], Emit&& emit) {
  const auto& P = tr.pieces();
  const auto& E = tr.extrema();
  std::vector<double> ts;
  for (size_t i = 0; i < P.size(); ++i) {
    const TrackPiece& pc = P[i];
    walk_piece<kEmit, Style>(pc, E.data() + pc.ext_begin, pc.ext_end - pc.ext_begin,
                             i + 1 == P.size() && tr.closed(), wg, node, emit, ts);
  }
}

}  // namespace polarcam
