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
#include <cmath>
#include <cstdint>
#include <vector>

#include "digitizer/axis_track.hpp"
#include "digitizer/level_crossing.hpp"

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
