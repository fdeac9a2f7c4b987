#include "digitizer/theta_rho.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "cam/error.hpp"
#include "digitizer/track_builder.hpp"

namespace polarcam {

ThetaRhoTrack ThetaRhoTrack::build(const Curve& path, double c) {
  if (!std::isfinite(c)) throw InputError("the arm's coupling must be a finite length per radian");
  ThetaRhoTrack tr;
  tr.c_ = c;
  build_axis_track(path, ThetaRhoMap{PolarMap{path.rounding_scale()}, c}, tr);
  return tr;
}

DigitizeResult digitize(const ThetaRhoTrack& track, const Grid& grid, StepRule rule, const SpeedProfile& profile,
                        StepSink* sink) {
  return digitize_arm(track, track.coupling(), grid, rule, profile, sink);
}


namespace {

void check_timing_radius(double r_floor) {
  if (!std::isfinite(r_floor) || r_floor < 0.0)
    throw InputError("the timing radius at the centre must be a finite length >= 0");
}

// Axis coordinates at fraction f of the segment a -> b (evaluated the same way at both ends of every piece, so
// consecutive pieces share their end points exactly; f = 0 and f = 1 give the vertices themselves).
void segment_coords(const ThetaRho& a, const ThetaRho& b, double c, double f, double q[2]) {
  const double th = f == 1.0 ? b.theta : a.theta + (b.theta - a.theta) * f;
  const double rho = f == 1.0 ? b.rho : a.rho + (b.rho - a.rho) * f;
  q[0] = rho + c * th;
  q[1] = th;
}

// The pieces of the part [fa, fb] of segment a -> b (path parameter u0 at a), out(piece, fa, fb) for each in
// order with its own fractions of the segment; their s0 is left for the caller (the running sum of the lengths
// before them).
template <class Out>
void segment_pieces(const ThetaRho& a, const ThetaRho& b, double u0, double c, double r_floor, double fa, double fb,
                    int depth, Out& out) {
  constexpr int N = kChebMaxDegree;
  const double dth = b.theta - a.theta, drho = b.rho - a.rho, half = 0.5 * (fb - fa);
  const auto& tp = cheb_points();
  std::array<double, N + 1> fv{};
  double mv = 0.0;
  for (int j = 0; j <= N; ++j) {
    const double f = fa + half * (1.0 + tp[j]);
    const double rho = std::max(a.rho + drho * f, r_floor);
    fv[j] = half * std::sqrt(drho * drho + rho * rho * dth * dth);
    mv = std::max(mv, fv[j]);
  }
  const double tol_v = 1e-14 * mv + 1e-300;
  TrackPiece pc;
  bool ok = false;
  for (int stride : {2, 1}) {
    std::array<double, N + 1> g{};
    const int n = N / stride;
    for (int j = 0; j <= n; ++j) g[j] = fv[j * stride];
    pc.V = cheb_fit(g.data(), n);
    if (cheb_tail(pc.V) <= tol_v) {
      cheb_chop(pc.V, tol_v);
      ok = true;
      break;
    }
  }
  if (!ok && depth < 60) {
    const double fm = 0.5 * (fa + fb);
    segment_pieces(a, b, u0, c, r_floor, fa, fm, depth + 1, out);
    segment_pieces(a, b, u0, c, r_floor, fm, fb, depth + 1, out);
    return;
  }
  if (!ok) cheb_chop(pc.V, tol_v);
  pc.ua = u0 + fa;
  pc.ub = u0 + fb;
  segment_coords(a, b, c, fa, pc.q_a);
  segment_coords(a, b, c, fb, pc.q_b);
  for (int k = 0; k < 2; ++k) {
    const double d = pc.q_b[k] - pc.q_a[k];
    pc.Q[k] = Cheb{};
    pc.Q[k].deg = 1;
    pc.Q[k].c[0] = 0.5 * d;
    pc.Q[k].c[1] = 0.5 * d;
    pc.dQ[k] = pc.Q[k].derivative();
  }
  pc.S = pc.V.integral();
  pc.len = pc.S(1.0);
  out(pc, fa, fb);
}

// Every piece of a theta-rho polyline's track in order, out(piece, k, fa, fb) for segment k (s0 not set): one piece a segment, split
// where rho crosses r_floor (the timing length's rate has a kink there) and where one series does not fit.
// Throws InputError naming the segment whose timing length is zero.
template <class Out>
void polyline_pieces(const ThetaRhoPath& path, double c, double r_floor, Out&& out) {
  const auto& v = path.vertices();
  for (size_t k = 0; k + 1 < v.size(); ++k) {
    const ThetaRho& a = v[k];
    const ThetaRho& b = v[k + 1];
    const double dth = b.theta - a.theta, drho = b.rho - a.rho;
    if (drho == 0.0 && dth != 0.0 && a.rho == 0.0 && r_floor == 0.0)
      throw InputError("the arm turns at the centre without moving the ball; give the machine's "
                       "max_angular_speed so that the turn can be timed",
                       "segment " + std::to_string(k + 1) + " (points " + std::to_string(k + 1) + "-" +
                           std::to_string(k + 2) + ")");
    double fs[3] = {0.0, 1.0, 1.0};
    int nf = 2;
    if (r_floor > 0.0 && drho != 0.0) {
      const double f = (r_floor - a.rho) / drho;
      if (f > 0.0 && f < 1.0) fs[1] = f, nf = 3;
    }
    auto seg_out = [&](const TrackPiece& pc, double fa, double fb) { out(pc, k, fa, fb); };
    for (int i = 0; i + 1 < nf; ++i)
      segment_pieces(a, b, static_cast<double>(k), c, r_floor, fs[i], fs[i + 1], 0, seg_out);
  }
}

// The running arc length of the pieces as AxisTrack::finish sums it (compensated), so that s0 is the same.
struct ArcSum {
  double s = 0.0, comp = 0.0;
  void add(TrackPiece& pc) {
    pc.s0 = s;
    const double y = pc.len - comp, t = s + y;
    comp = (t - s) - y;
    s = t;
  }
};

}  // namespace

// A pattern that ends where it starts in the plane ends on its start node only when the arm comes back too: at the
// centre (rho 0) the ball is in the same place whatever theta, but an arm that turned by other than whole turns
// ends on another angular node, and the tape is not periodic (an open path, for the motors). Sets the track's
// closed flag and its winding (the whole turns the arm made; 0 for an open path).
namespace {
void close_for_the_axes(const ThetaRhoPath& path, bool& closed, int& winding) {
  const auto& v = path.vertices();
  const double turns = (v.back().theta - v.front().theta) / PolarMap::kTwoPi;
  closed = path.closed() && std::abs(turns - std::nearbyint(turns)) * PolarMap::kTwoPi <= 1e-9;
  winding = closed ? static_cast<int>(std::nearbyint(turns)) : 0;
}
}  // namespace

// Fills an axis track from a theta-rho polyline (the friend of AxisTrack that sets its pieces).
struct PolylineTrackFill {
  static void fill(AxisTrack& tr, const ThetaRhoPath& path, double c, double r_floor) {
    check_timing_radius(r_floor);
    const auto& v = path.vertices();
    tr.pieces_.clear();
    tr.extrema_.clear();
    tr.turns_.clear();
    close_for_the_axes(path, tr.closed_, tr.winding_);
    tr.pieces_.reserve(v.size() - 1);  // one piece a segment as a rule
    polyline_pieces(path, c, r_floor, [&](const TrackPiece& pc, size_t, double, double) { tr.pieces_.push_back(pc); });
    tr.finish();
  }
};

PolylineTrack::PolylineTrack(const ThetaRhoPath& path, double c, double r_floor) : path_(&path), c_(c), r_floor_(r_floor) {
  if (!std::isfinite(c)) throw InputError("the arm's coupling must be a finite length per radian");
  check_timing_radius(r_floor);
  const auto& v = path.vertices();
  close_for_the_axes(path, closed_, winding_);
  // the ranges as AxisTrack::finish finds them: the start of every piece, then the end of the last (the pieces
  // are linear in both coordinates: no interior extrema); rho is the polar track's q0
  for (int a = 0; a < 2; ++a) {
    qmin_[a] = {std::numeric_limits<double>::infinity(), 0, -1};
    qmax_[a] = {-std::numeric_limits<double>::infinity(), 0, -1};
  }
  rmin_ = qmin_[0];
  rmax_ = qmax_[0];
  auto consider = [&](size_t i, double t, const double q[2], double rho) {
    for (int a = 0; a < 2; ++a) {
      if (q[a] < qmin_[a].value) qmin_[a] = {q[a], i, t};
      if (q[a] > qmax_[a].value) qmax_[a] = {q[a], i, t};
    }
    if (rho < rmin_.value) rmin_ = {rho, i, t};
    if (rho > rmax_.value) rmax_ = {rho, i, t};
  };
  ArcSum sum;
  double rho_b = 0.0;
  polyline_pieces(path, c, r_floor, [&](const TrackPiece& p, size_t k, double fa, double fb) {
    TrackPiece pc = p;
    sum.add(pc);
    double polar[2];  // as the polar track's piece has them
    segment_coords(v[k], v[k + 1], 0.0, fa, polar);
    consider(n_, -1.0, pc.q_a, polar[0]);
    segment_coords(v[k], v[k + 1], 0.0, fb, polar);
    rho_b = polar[0];
    if (n_ == 0) front_ = pc;
    back_ = pc;
    ++n_;
  });
  length_ = sum.s;
  consider(n_ - 1, 1.0, back_.q_b, rho_b);
}

void PolylineTrack::visit(void (*f)(void*, size_t, const TrackPiece&), void* ctx, bool polar) const {
  ArcSum sum;
  size_t i = 0;
  polyline_pieces(*path_, polar ? 0.0 : c_, r_floor_, [&](const TrackPiece& p, size_t, double, double) {
    TrackPiece pc = p;
    sum.add(pc);
    f(ctx, i++, pc);
  });
}

TrackPiece PolylineTrack::piece(size_t i, bool polar) const {
  TrackPiece out;
  for_each([&](size_t k, const TrackPiece& pc) {
    if (k == i) out = pc;
  }, polar);
  return out;
}

ThetaRhoTrack ThetaRhoTrack::build(const ThetaRhoPath& path, double c, double r_floor) {
  if (!std::isfinite(c)) throw InputError("the arm's coupling must be a finite length per radian");
  ThetaRhoTrack tr;
  tr.c_ = c;
  PolylineTrackFill::fill(tr, path, c, r_floor);
  return tr;
}

PolarTrack polyline_polar_track(const ThetaRhoPath& path, double r_floor) {
  PolarTrack tr;
  PolylineTrackFill::fill(tr, path, 0.0, r_floor);
  return tr;
}

}  // namespace polarcam
