#include "digitizer/digitize.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "cam/error.hpp"
#include "digitizer/level_crossing.hpp"

namespace polarcam {

const char* to_string(StepRule r) { return r == StepRule::nearest ? "nearest" : "thesis"; }

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::string fmt(double v, int prec = 6) {
  std::ostringstream os;
  os.precision(prec);
  os << v;
  return os.str();
}

std::string where(const PolarTrack& tr, const TrackExtent& e, double shift) {
  const TrackPiece& p = tr.pieces()[e.piece];
  double r = tr.r(e.piece, e.t), th = tr.theta(e.piece, e.t) + shift;
  return "at path parameter " + fmt(p.u_at(e.t)) + " (r = " + fmt(r * 1e3) + " mm, theta = " + fmt(th) +
         " rad, machine x = " + fmt(r * std::cos(th) * 1e3) + " mm, y = " + fmt(r * std::sin(th) * 1e3) + " mm)";
}

struct PieceGrid {  // a piece in grid units
  Cheb g[2];
  double base[2];  // value at t = -1
  double end[2];   // value at t = +1
};

void to_grid(const TrackPiece& p, const Grid& grid, double shift, PieceGrid& pg) {
  pg.g[0] = p.R;
  pg.g[0].scale(1.0 / grid.dr);
  pg.g[1] = p.Th;
  pg.g[1].scale(1.0 / grid.dtheta);
  pg.base[0] = p.r_a / grid.dr;
  pg.base[1] = (p.th_a + shift) / grid.dtheta;
  pg.end[0] = p.r_b / grid.dr;
  pg.end[1] = (p.th_b + shift) / grid.dtheta;
}

struct Emitter {
  const SpeedProfile* profile;
  StepSink* sink;
  DigitizeResult* res;
  int64_t last_ns = 0;
  int64_t last_axis_ns[2] = {0, 0};
  uint64_t count[2] = {0, 0};

  void emit(int axis, int dir, double s) {
    double t = profile->time_at(s);
    int64_t ns = std::llround(t * 1e9);
    if (ns < last_ns) ns = last_ns;
    last_ns = ns;
    AxisSummary& ax = axis == kAxisRadial ? res->radial : res->angular;
    if (count[axis] > 0) {
      int64_t iv = ns - last_axis_ns[axis];
      if (ax.min_interval_ns < 0 || iv < ax.min_interval_ns) ax.min_interval_ns = iv;
    }
    ++count[axis];
    last_axis_ns[axis] = ns;
    (dir > 0 ? ax.plus : ax.minus) += 1;
    if (sink) sink->step(axis, dir, ns);
  }
};

struct Cursor {
  int dir = 0;
  bool has = false;
  double level = 0, t = 0, s = 0;  // pending event
  double lo = 0, flo = 0;          // bracket start and g(lo) - level
  double hist[3] = {0, 0, 0};
  int nh = 0;
};

// The quantiser over all pieces. With kEmit false only the nodes are tracked (no root finding).
template <bool kEmit>
void run(const PolarTrack& tr, const Grid& grid, double shift, double h, double closed_end_m, int64_t node[2],
         Emitter* em) {
  const auto& P = tr.pieces();
  const auto& E = tr.extrema();
  PieceGrid pg;
  std::vector<double> ts;
  for (size_t i = 0; i < P.size(); ++i) {
    const TrackPiece& pc = P[i];
    to_grid(pc, grid, shift, pg);
    if (i + 1 == P.size() && tr.closed() && !std::isnan(closed_end_m)) pg.end[1] = closed_end_m;
    ts.clear();
    ts.push_back(-1.0);
    for (uint32_t k = pc.ext_begin; k < pc.ext_end; ++k) ts.push_back(E[k]);
    ts.push_back(1.0);
    double fprev[2] = {pg.base[0], pg.base[1]};
    for (size_t k = 0; k + 1 < ts.size(); ++k) {
      const double tl = ts[k], trr = ts[k + 1];
      double fend[2];
      for (int a = 0; a < 2; ++a) fend[a] = (k + 2 == ts.size()) ? pg.end[a] : pg.base[a] + pg.g[a](trr);
      if constexpr (!kEmit) {
        for (int a = 0; a < 2; ++a) {
          if (fend[a] > fprev[a]) {
            double v = std::floor(fend[a] - h) + 1.0;
            if (v > static_cast<double>(node[a])) node[a] = static_cast<int64_t>(v);
          } else if (fend[a] < fprev[a]) {
            double v = std::floor(fend[a] + h);
            if (v < static_cast<double>(node[a])) node[a] = static_cast<int64_t>(v);
          }
        }
      } else {
        Cursor cur[2];
        auto advance = [&](int a) {
          Cursor& c = cur[a];
          c.has = false;
          if (c.dir == 0) return;
          double level = static_cast<double>(node[a]) + (c.dir > 0 ? h : -h);
          bool fires = c.dir > 0 ? (fend[a] >= level) : (fend[a] < level);
          if (!fires) return;
          double y = level - pg.base[a];
          double flo = (c.nh > 0) ? c.level - level : fprev[a] - level;
          double guess = -2.0;
          if (c.nh >= 3)
            guess = 3.0 * c.hist[0] - 3.0 * c.hist[1] + c.hist[2];
          else if (c.nh == 2)
            guess = 2.0 * c.hist[0] - c.hist[1];
          LevelCrossing r = solve_crossing(pg.g[a], pc.S, y, c.lo, trr, flo, fend[a] - level, guess);
          c.has = true;
          c.level = level;
          c.t = r.t;
          c.s = r.s;
        };
        for (int a = 0; a < 2; ++a) {
          cur[a].dir = fend[a] > fprev[a] ? 1 : (fend[a] < fprev[a] ? -1 : 0);
          cur[a].lo = tl;
          advance(a);
        }
        while (cur[0].has || cur[1].has) {
          int a = (cur[0].has && (!cur[1].has || cur[0].t <= cur[1].t)) ? 0 : 1;
          Cursor& c = cur[a];
          em->emit(a, c.dir, pc.s0 + c.s);
          node[a] += c.dir;
          c.lo = c.t;
          c.hist[2] = c.hist[1];
          c.hist[1] = c.hist[0];
          c.hist[0] = c.t;
          if (c.nh < 3) ++c.nh;
          advance(a);
        }
      }
      fprev[0] = fend[0];
      fprev[1] = fend[1];
    }
  }
}

// Max over the path of V(s) |df/ds| / resolution for both axes, sampled and refined.
void max_rates(const PolarTrack& tr, const Grid& grid, const SpeedProfile& prof, DigitizeResult& res) {
  const auto& P = tr.pieces();
  auto rate = [&](size_t i, double t, int axis) {
    const TrackPiece& p = P[i];
    double v = p.V(t);
    if (!(v > 0.0)) return 0.0;
    double d = axis == 0 ? p.dR(t) / grid.dr : p.dTh(t) / grid.dtheta;
    return prof.speed_at(p.s0 + p.S(t)) * std::abs(d) / v;
  };
  for (int axis = 0; axis < 2; ++axis) {
    double best = -1.0, bt = 0.0;
    size_t bi = 0;
    constexpr int M = 8;  // per piece; the best sample is refined below
    for (size_t i = 0; i < P.size(); ++i)
      for (int j = 0; j <= M; ++j) {
        double t = -1.0 + 2.0 * j / M, r = rate(i, t, axis);
        if (r > best) {
          best = r;
          bi = i;
          bt = t;
        }
      }
    // golden-section refinement around the best sample
    double lo = std::max(-1.0, bt - 2.0 / M), hi = std::min(1.0, bt + 2.0 / M);
    const double g = 0.6180339887498949;
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = rate(bi, x1, axis), f2 = rate(bi, x2, axis);
    for (int it = 0; it < 60; ++it) {
      if (f1 > f2) {
        hi = x2;
        x2 = x1;
        f2 = f1;
        x1 = hi - g * (hi - lo);
        f1 = rate(bi, x1, axis);
      } else {
        lo = x1;
        x1 = x2;
        f1 = f2;
        x2 = lo + g * (hi - lo);
        f2 = rate(bi, x2, axis);
      }
    }
    best = std::max({best, f1, f2});
    (axis == 0 ? res.radial : res.angular).max_rate_hz = std::max(best, 0.0);
  }
}

}  // namespace

double place_on_grid(const PolarTrack& tr, const Grid& grid) {
  grid.validate();
  const TrackExtent rmin = tr.r_min(), rmax = tr.r_max();
  double shift = 0.0;
  const TrackExtent thmin = tr.theta_min(), thmax = tr.theta_max();
  if (grid.theta_min) {
    // smallest whole-turn shift putting the path's lowest angle at or above theta_min
    double k = std::ceil((*grid.theta_min - thmin.value) / kTwoPi - 1e-12);
    shift = kTwoPi * k;
    if (thmax.value + shift > *grid.theta_max + 1e-12) {
      double span = thmax.value - thmin.value;
      if (span > *grid.theta_max - *grid.theta_min)
        throw InputError("the path leaves the work area: it sweeps " + fmt(span) + " rad about the pole, more than the " +
                         fmt(*grid.theta_max - *grid.theta_min) + " rad from theta_min " + fmt(*grid.theta_min) +
                         " to theta_max " + fmt(*grid.theta_max) + "; from " + where(tr, thmin, shift) + " to " +
                         where(tr, thmax, shift));
      throw InputError("the path leaves the work area: theta reaches " + fmt(thmax.value + shift) + " rad > theta_max " +
                       fmt(*grid.theta_max) + " rad " + where(tr, thmax, shift) + " while its lowest angle " +
                       fmt(thmin.value + shift) + " rad needs theta >= theta_min " + fmt(*grid.theta_min) + " rad");
    }
  } else {
    double a0 = tr.pieces().front().th_a;
    shift = -kTwoPi * std::floor(a0 / kTwoPi);
  }
  if (rmin.value < grid.r_min)
    throw InputError("the path leaves the work area: r falls to " + fmt(rmin.value * 1e3) + " mm < r_min " +
                     fmt(grid.r_min * 1e3) + " mm " + where(tr, rmin, shift));
  if (grid.r_max && rmax.value > *grid.r_max)
    throw InputError("the path leaves the work area: r reaches " + fmt(rmax.value * 1e3) + " mm > r_max " +
                     fmt(*grid.r_max * 1e3) + " mm " + where(tr, rmax, shift));
  return shift;
}

DigitizeResult digitize(const PolarTrack& tr, const Grid& grid, StepRule rule, const SpeedProfile& profile,
                        StepSink* sink) {
  DigitizeResult res;
  const double shift = place_on_grid(tr, grid);
  res.theta_shift = shift;
  res.closed = tr.closed();
  res.winding = tr.winding();
  res.path_length_m = tr.length();
  res.duration_s = profile.time_at(tr.length());
  res.duration_ns = std::llround(res.duration_s * 1e9);

  const double h = rule == StepRule::nearest ? 0.5 : 1.0;
  const TrackPiece& first = tr.pieces().front();
  const double f0[2] = {first.r_a / grid.dr, (first.th_a + shift) / grid.dtheta};
  // a closed path ends at its start advanced by whole turns; with a whole number of steps per turn its end value
  // in angular steps is exact
  const double closed_end_m = (tr.closed() && grid.steps_per_rev > 0)
                                  ? f0[1] + static_cast<double>(tr.winding()) * static_cast<double>(grid.steps_per_rev)
                                  : std::nan("");
  int64_t node[2];
  for (int a = 0; a < 2; ++a)
    node[a] = static_cast<int64_t>(rule == StepRule::nearest ? std::floor(f0[a] + 0.5) : std::floor(f0[a]));
  if (rule == StepRule::thesis && tr.closed()) {
    // start from the node the quantiser holds after one lap, so the tape is periodic
    int64_t lap[2] = {node[0], node[1]};
    run<false>(tr, grid, shift, h, closed_end_m, lap, nullptr);
    node[0] = lap[0];
    if (grid.steps_per_rev > 0 || tr.winding() == 0)
      node[1] = lap[1] - static_cast<int64_t>(tr.winding()) * grid.steps_per_rev;
  }
  res.start_n = node[0];
  res.start_m = node[1];

  Emitter em{&profile, sink, &res};
  run<true>(tr, grid, shift, h, closed_end_m, node, &em);
  res.end_n = node[0];
  res.end_m = node[1];
  res.last_step_ns = em.last_ns;
  if (res.duration_ns < res.last_step_ns) res.duration_ns = res.last_step_ns;

  if (tr.closed()) {
    res.returns_to_start = res.end_n == res.start_n &&
                           (grid.steps_per_rev > 0
                                ? res.end_m == res.start_m + static_cast<int64_t>(tr.winding()) * grid.steps_per_rev
                                : res.end_m == res.start_m);
    if (!res.returns_to_start && (grid.steps_per_rev > 0 || tr.winding() == 0))
      throw std::logic_error("internal error: a closed path did not return to its start node");
  }
  max_rates(tr, grid, profile, res);
  return res;
}

}  // namespace polarcam
