#include "digitizer/digitize.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "digitizer/step_walker.hpp"
#include "digitizer/theta_rho.hpp"

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

// How the digitizer reads a track: an AxisTrack holds its pieces (and their interior extrema); a PolylineTrack
// makes each piece as it is visited (it has no interior extrema: both coordinates are linear on every piece).
// f(index, piece, extrema, number of extrema) for every piece in order.
template <class F>
void for_each_piece(const AxisTrack& tr, F&& f) {
  const auto& P = tr.pieces();
  const auto& E = tr.extrema();
  for (size_t i = 0; i < P.size(); ++i) f(i, P[i], E.data() + P[i].ext_begin, size_t{P[i].ext_end - P[i].ext_begin});
}
template <class F>
void for_each_piece(const PolylineTrack& tr, F&& f) {
  tr.for_each([&](size_t i, const TrackPiece& pc) { f(i, pc, static_cast<const double*>(nullptr), size_t{0}); });
}
const TrackPiece& piece_at(const AxisTrack& tr, size_t i) { return tr.pieces()[i]; }
TrackPiece piece_at(const PolylineTrack& tr, size_t i) { return tr.piece(i); }
size_t piece_count(const AxisTrack& tr) { return tr.pieces().size(); }
size_t piece_count(const PolylineTrack& tr) { return tr.size(); }
const TrackPiece& first_piece(const AxisTrack& tr) { return tr.pieces().front(); }
const TrackPiece& first_piece(const PolylineTrack& tr) { return tr.front(); }
const TrackPiece& last_piece(const AxisTrack& tr) { return tr.pieces().back(); }
const TrackPiece& last_piece(const PolylineTrack& tr) { return tr.back(); }

// Walks every piece of the track (walk_piece).
template <bool kEmit, class Style, class Track, class Emit>
void walk_all(const Track& tr, const WalkGrid& wg, int64_t node[2], Emit&& emit) {
  std::vector<double> ts;
  const size_t n = piece_count(tr);
  for_each_piece(tr, [&](size_t i, const TrackPiece& pc, const double* ext, size_t n_ext) {
    walk_piece<kEmit, Style>(pc, ext, n_ext, i + 1 == n && tr.closed(), wg, node, emit, ts);
  });
}

// The point of an extent; the radial motor stands at q = r + c theta (theta before the shift).
template <class Track>
std::string where(const Track& tr, const TrackExtent& e, double shift, double c) {
  const TrackPiece& p = piece_at(tr, e.piece);
  const double th0 = p.q_a[1] + p.Q[1](e.t), r = p.q_a[0] + p.Q[0](e.t) - c * th0, th = th0 + shift;
  return "at path parameter " + fmt(p.u_at(e.t)) + " (r = " + fmt(r * 1e3) + " mm, theta = " + fmt(th) +
         " rad, machine x = " + fmt(r * std::cos(th) * 1e3) + " mm, y = " + fmt(r * std::sin(th) * 1e3) + " mm)";
}

// Range of r = q0 - c q1 over a coupled arm's track: the ends of the pieces and the roots of dQ0 - c dQ1.
template <class Track>
void ball_radius_range(const Track& tr, double c, TrackExtent& lo, TrackExtent& hi) {
  lo = {std::numeric_limits<double>::infinity(), 0, -1.0};
  hi = {-std::numeric_limits<double>::infinity(), 0, -1.0};
  auto consider = [&](const TrackPiece& p, size_t i, double t) {
    const double r = (p.q_a[0] + p.Q[0](t)) - c * (p.q_a[1] + p.Q[1](t));
    if (r < lo.value) lo = {r, i, t};
    if (r > hi.value) hi = {r, i, t};
  };
  std::vector<double> roots;
  for_each_piece(tr, [&](size_t i, const TrackPiece& p, const double*, size_t) {
    consider(p, i, -1.0);
    Cheb d = p.dQ[1];
    d.scale(-c);
    for (int k = 0; k <= std::max(d.deg, p.dQ[0].deg); ++k) d.c[k] = (k <= d.deg ? d.c[k] : 0.0) + (k <= p.dQ[0].deg ? p.dQ[0].c[k] : 0.0);
    d.deg = std::max(d.deg, p.dQ[0].deg);
    roots.clear();
    cheb_sign_changes(d, roots);
    for (double t : roots) consider(p, i, t);
  });
  consider(last_piece(tr), piece_count(tr) - 1, 1.0);
}

// std::llround (halves away from zero) inline: x - trunc(x) is exact, so the comparisons with 1/2 decide as
// llround does; outside the range of int64_t (and for NaN) llround itself.
inline int64_t round_ns(double x) {
  if (!(std::abs(x) < 4e18)) return std::llround(x);
  const int64_t r = static_cast<int64_t>(x);  // trunc(x); exact as a double (|x| >= 2^53 is a whole number)
  const double d = x - static_cast<double>(r);
  return r + (d >= 0.5 ? 1 : 0) - (d <= -0.5 ? 1 : 0);
}

struct Emitter {
  const SpeedProfile* profile;
  StepSink* sink;
  DigitizeResult* res;
  int64_t t0_ns = 0;  // the track's start on the tape's clock
  int64_t last_ns = 0;
  int64_t last_axis_ns[2] = {0, 0};
  uint64_t count[2] = {0, 0};

  // How far the arc length of a step on [sa, sb] may be off (the step walker's inverse, level_inverse.hpp): the
  // time it moves is at most that over the least speed there, here kTimeTolerance; 0 (solve every crossing)
  // where the profile knows no positive least speed.
  static constexpr double kTimeTolerance = 1e-12;  // s
  double arc_tolerance(double sa, double sb) const { return kTimeTolerance * profile->min_speed(sa, sb); }

  void operator()(int axis, int dir, double s) {
    double t = profile->time_at(s);
    int64_t ns = round_ns(t * 1e9);
    if (ns < last_ns) ns = last_ns;
    last_ns = ns;
    ns += t0_ns;
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

// The digitizer's walk: the arc length rides in the solver (most crossings are steps), guesses are quadratic.
using DigitizerStyle = WalkStyle<true, 3>;

// Max over the path of V(s) |df/ds| / resolution for both axes, sampled and refined. One pass over the pieces
// for both axes (each axis keeps a copy of the piece of its best sample).
template <class Track>
void max_rates(const Track& tr, const Grid& grid, const SpeedProfile& prof, DigitizeResult& res) {
  auto rate = [&](const TrackPiece& p, double t, int axis) {
    double v = p.V(t);
    if (!(v > 0.0)) return 0.0;
    double d = axis == 0 ? p.dQ[0](t) / grid.dr : p.dQ[1](t) / grid.dtheta;
    return prof.speed_at(p.s0 + p.S(t)) * std::abs(d) / v;
  };
  constexpr int M = 8;  // per piece; the best sample is refined below
  double bests[2] = {-1.0, -1.0}, bts[2] = {0.0, 0.0};
  TrackPiece bps[2] = {first_piece(tr), first_piece(tr)};
  for_each_piece(tr, [&](size_t, const TrackPiece& p, const double*, size_t) {
    for (int axis = 0; axis < 2; ++axis) {
      bool better = false;
      for (int j = 0; j <= M; ++j) {
        double t = -1.0 + 2.0 * j / M, r = rate(p, t, axis);
        if (r > bests[axis]) {
          bests[axis] = r;
          bts[axis] = t;
          better = true;
        }
      }
      if (better) bps[axis] = p;
    }
  });
  for (int axis = 0; axis < 2; ++axis) {
    double best = bests[axis], bt = bts[axis];
    const TrackPiece& bp = bps[axis];
    // golden-section refinement around the best sample
    double lo = std::max(-1.0, bt - 2.0 / M), hi = std::min(1.0, bt + 2.0 / M);
    const double g = 0.6180339887498949;
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = rate(bp, x1, axis), f2 = rate(bp, x2, axis);
    for (int it = 0; it < 60; ++it) {
      if (f1 > f2) {
        hi = x2;
        x2 = x1;
        f2 = f1;
        x1 = hi - g * (hi - lo);
        f1 = rate(bp, x1, axis);
      } else {
        lo = x1;
        x1 = x2;
        f1 = f2;
        x2 = lo + g * (hi - lo);
        f2 = rate(bp, x2, axis);
      }
    }
    best = std::max({best, f1, f2});
    (axis == 0 ? res.radial : res.angular).max_rate_hz = std::max(best, 0.0);
  }
}

template <class Track>
void check_radius(const Track& tr, double c, const Grid& grid, double shift);

template <class Track>
double place_on_grid_impl(const Track& tr, double c, const Grid& grid) {
  grid.validate();
  double shift = 0.0;
  const TrackExtent thmin = tr.q_min(1), thmax = tr.q_max(1);
  if (grid.theta_min) {
    // smallest whole-turn shift putting the path's lowest angle at or above theta_min
    double k = std::ceil((*grid.theta_min - thmin.value) / kTwoPi - 1e-12);
    shift = kTwoPi * k;
    if (thmax.value + shift > *grid.theta_max + 1e-12) {
      double span = thmax.value - thmin.value;
      if (span > *grid.theta_max - *grid.theta_min)
        throw InputError("the path leaves the work area: it sweeps " + fmt(span) + " rad about the pole, more than the " +
                         fmt(*grid.theta_max - *grid.theta_min) + " rad from theta_min " + fmt(*grid.theta_min) +
                         " to theta_max " + fmt(*grid.theta_max) + "; from " + where(tr, thmin, shift, c) + " to " +
                         where(tr, thmax, shift, c));
      throw InputError("the path leaves the work area: theta reaches " + fmt(thmax.value + shift) + " rad > theta_max " +
                       fmt(*grid.theta_max) + " rad " + where(tr, thmax, shift, c) + " while its lowest angle " +
                       fmt(thmin.value + shift) + " rad needs theta >= theta_min " + fmt(*grid.theta_min) + " rad");
    }
  } else {
    double a0 = first_piece(tr).q_a[1];
    shift = -kTwoPi * std::floor(a0 / kTwoPi);
  }
  check_radius(tr, c, grid, shift);
  return shift;
}

// The work area's radii about the track (whatever its angular branch).
template <class Track>
void check_radius(const Track& tr, double c, const Grid& grid, double shift) {
  // the work area bounds the ball's (tool's) radius r = q0 - c q1: r itself on a polar machine; on a coupled arm
  // the radial motor is geared to the arm and has no travel of its own to bound
  TrackExtent rmin = tr.q_min(0), rmax = tr.q_max(0);
  if (c != 0.0) ball_radius_range(tr, c, rmin, rmax);
  // the ball's r on a coupled arm is q0 - c q1, rounded at the size of c theta: a thousandth of a step is slack;
  // on a polar machine 1e-12 m (as theta's 1e-12 rad): the rounding of a track built another way, such as the pole
  // search's, which may put a pole where the path touches r_max
  const double slack = c == 0.0 ? 1e-12 : 1e-3 * grid.dr;
  if (rmin.value < grid.r_min - slack)
    throw InputError("the path leaves the work area: r falls to " + fmt(rmin.value * 1e3) + " mm < r_min " +
                     fmt(grid.r_min * 1e3) + " mm " + where(tr, rmin, shift, c));
  if (grid.r_max && rmax.value > *grid.r_max + slack)
    throw InputError("the path leaves the work area: r reaches " + fmt(rmax.value * 1e3) + " mm > r_max " +
                     fmt(*grid.r_max * 1e3) + " mm " + where(tr, rmax, shift, c));
}
template <class Track>
void check_on_grid_impl(const Track& tr, double c, const Grid& grid, double shift) {
  grid.validate();
  if (grid.theta_min) {
    const TrackExtent thmin = tr.q_min(1), thmax = tr.q_max(1);
    if (thmin.value + shift < *grid.theta_min - 1e-12)
      throw InputError("the path leaves the work area: theta falls to " + fmt(thmin.value + shift) + " rad < theta_min " +
                       fmt(*grid.theta_min) + " rad " + where(tr, thmin, shift, c));
    if (thmax.value + shift > *grid.theta_max + 1e-12)
      throw InputError("the path leaves the work area: theta reaches " + fmt(thmax.value + shift) + " rad > theta_max " +
                       fmt(*grid.theta_max) + " rad " + where(tr, thmax, shift, c));
  }
  check_radius(tr, c, grid, shift);
}

// How the track's coordinates meet the grid's steps, on the angular branch `shift`.
template <class Track>
WalkGrid walk_grid(const Track& tr, double c, const Grid& grid, StepRule rule, double shift) {
  WalkGrid wg;
  wg.res[0] = grid.dr;
  wg.res[1] = grid.dtheta;
  wg.offset[0] = c * shift;  // the radial motor turns with the arm's whole-turn shift
  wg.offset[1] = shift;
  wg.h = rule == StepRule::nearest ? 0.5 : 1.0;
  // a closed path ends at its start advanced by whole turns; with a whole number of steps per turn its end value
  // in angular steps is exact
  if (tr.closed() && grid.steps_per_rev > 0)
    wg.last_end[1] = (first_piece(tr).q_a[1] + shift) / grid.dtheta +
                     static_cast<double>(tr.winding()) * static_cast<double>(grid.steps_per_rev);
  return wg;
}

// The node a tape of the track starts on: the quantisers' value at the path's start; with the thesis rule on a
// closed path the node they hold after one lap, so that the tape is periodic.
template <class Track>
void start_nodes(const Track& tr, double c, const Grid& grid, StepRule rule, const WalkGrid& wg, int64_t node[2]) {
  const TrackPiece& first = first_piece(tr);
  const double f0[2] = {(first.q_a[0] + wg.offset[0]) / grid.dr, (first.q_a[1] + wg.offset[1]) / grid.dtheta};
  for (int a = 0; a < 2; ++a)
    node[a] = static_cast<int64_t>(rule == StepRule::nearest ? std::floor(f0[a] + 0.5) : std::floor(f0[a]));
  if (rule == StepRule::thesis && tr.closed()) {
    // the radial motor of a coupled arm ends 2 pi c per turn away from its start
    const bool radial_closes = c == 0.0 || tr.winding() == 0;
    int64_t lap[2] = {node[0], node[1]};
    walk_all<false, DigitizerStyle>(tr, wg, lap, [](int, int, double) {});
    if (radial_closes) node[0] = lap[0];
    if (grid.steps_per_rev > 0 || tr.winding() == 0)
      node[1] = lap[1] - static_cast<int64_t>(tr.winding()) * grid.steps_per_rev;
  }
}

// The walk of digitize_arm and digitize_arm_from: `from` null starts on the track's own start node.
template <class Track>
DigitizeResult walk_track(const Track& tr, double c, const Grid& grid, StepRule rule, const SpeedProfile& profile,
                          StepSink* sink, double shift, const int64_t* from, int64_t t0_ns) {
  DigitizeResult res;
  res.theta_shift = shift;
  res.closed = tr.closed();
  res.winding = tr.winding();
  res.path_length_m = tr.length();
  res.duration_s = profile.time_at(tr.length());
  if (!(res.duration_s * 1e9 <= kMaxDurationNs))
    throw InputError("the path takes " + significant(res.duration_s, 3) +
                     " s, longer than a tape can time (2^62 ns, about 146 years): raise the speed");
  res.duration_ns = std::llround(res.duration_s * 1e9);
  // A tape times steps in whole nanoseconds: a step rate above 1e9 per second cannot be told apart.
  max_rates(tr, grid, profile, res);
  for (const auto& [ax, name] : {std::pair{&res.radial, "radial"}, std::pair{&res.angular, "angular"}})
    if (!(ax->max_rate_hz <= 1e9))
      throw InputError(std::string("the ") + name + " step rate reaches " + significant(ax->max_rate_hz, 3) +
                       " Hz, beyond the tape's 1 ns tick (at most 1e9 steps per second): lower the speed at least " +
                       significant(ax->max_rate_hz / 1e9 * 1.001, 3) + " times");

  const WalkGrid wg = walk_grid(tr, c, grid, rule, shift);
  const bool radial_closes = c == 0.0 || tr.winding() == 0;
  int64_t node[2];
  if (from) {
    node[0] = from[0];
    node[1] = from[1];
  } else {
    start_nodes(tr, c, grid, rule, wg, node);
  }
  res.start_n = node[0];
  res.start_m = node[1];
  if (sink && !from) sink->begin(node[0], node[1]);

  Emitter em{&profile, sink, &res, t0_ns};
  walk_all<true, DigitizerStyle>(tr, wg, node, em);
  res.end_n = node[0];
  res.end_m = node[1];
  res.last_step_ns = em.last_ns;
  if (res.duration_ns < res.last_step_ns) res.duration_ns = res.last_step_ns;

  if (tr.closed() && !from) {
    res.returns_to_start = res.end_n == res.start_n &&
                           (grid.steps_per_rev > 0
                                ? res.end_m == res.start_m + static_cast<int64_t>(tr.winding()) * grid.steps_per_rev
                                : res.end_m == res.start_m);
    if (!res.returns_to_start && radial_closes && (grid.steps_per_rev > 0 || tr.winding() == 0))
      throw std::logic_error("internal error: a closed path did not return to its start node");
  }
  return res;
}

}  // namespace

double place_on_grid_arm(const AxisTrack& tr, double c, const Grid& grid) { return place_on_grid_impl(tr, c, grid); }

void check_on_grid_arm(const AxisTrack& tr, double c, const Grid& grid, double shift) {
  check_on_grid_impl(tr, c, grid, shift);
}

double place_on_grid(const PolarTrack& tr, const Grid& grid) { return place_on_grid_arm(tr, 0.0, grid); }

DigitizeResult digitize(const PolylineTrack& tr, const Grid& grid, StepRule rule, const SpeedProfile& profile,
                        StepSink* sink) {
  const double shift = place_on_grid_impl(tr, tr.coupling(), grid);
  return walk_track(tr, tr.coupling(), grid, rule, profile, sink, shift, nullptr, 0);
}

DigitizeResult digitize_arm(const AxisTrack& tr, double c, const Grid& grid, StepRule rule,
                            const SpeedProfile& profile, StepSink* sink) {
  const double shift = place_on_grid_impl(tr, c, grid);
  return walk_track(tr, c, grid, rule, profile, sink, shift, nullptr, 0);
}

DigitizeResult digitize_arm_from(const AxisTrack& tr, double c, const Grid& grid, StepRule rule,
                                 const SpeedProfile& profile, StepSink* sink, double shift,
                                 const int64_t start_node[2], int64_t t0_ns) {
  check_on_grid_impl(tr, c, grid, shift);
  return walk_track(tr, c, grid, rule, profile, sink, shift, start_node, t0_ns);
}

DigitizeResult digitize(const PolarTrack& tr, const Grid& grid, StepRule rule, const SpeedProfile& profile,
                        StepSink* sink) {
  return digitize_arm(tr, 0.0, grid, rule, profile, sink);
}

std::array<int64_t, 2> start_node(const PolarTrack& tr, const Grid& grid, StepRule rule) {
  const double shift = place_on_grid_impl(tr, 0.0, grid);
  std::array<int64_t, 2> node{};
  start_nodes(tr, 0.0, grid, rule, walk_grid(tr, 0.0, grid, rule, shift), node.data());
  return node;
}

}  // namespace polarcam
