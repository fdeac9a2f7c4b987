#pragma once
// The one track builder: fits a path's axis coordinates q0(u), q1(u) and arc length s(u) with adaptive
// piecewise Chebyshev series (axis_track.hpp), whatever the kinematics. The kinematics enter through an axis map,
// a small class with
//   bool coords(Vec2 p, const double ref[2], double q[2], double& aux) const
//       the axis coordinates of the path point p (m, in the frame of the map's centre), an angle unwrapped
//       against ref (the coordinates of a nearby sample); aux is a scale the tolerances need (the distance from
//       the pole for an angle). False when p is a singularity of the map (the pole).
//   bool smooth(const double a[2], const double b[2]) const
//       false when two neighbouring samples are too far apart for one series (an angle jumping near the pole).
//   void tolerances(const double qa[2], const double span[2], double aux_min, double tol[2]) const
//       the absolute accuracy asked of each coordinate on a piece starting at qa, spanning |q - qa| <= span.
//   int close(const double first[2], double last[2]) const
//       a closed path ends where it starts: sets its end coordinates from the start ones, returns its winding.
//   static constexpr const char* kFrame, kSingular, kRough
//       words of the error messages: the frame of the printed point ("machine " or ""), what a singular point
//       is ("passes through the machine pole"), why a path cannot be resolved.
// Everything is inline and resolved at compile time; the builder is instantiated once a kinematics.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "cam/curve.hpp"
#include "cam/error.hpp"
#include "digitizer/axis_track.hpp"

namespace polarcam {

template <class Map>
class TrackBuilder {
 public:
  TrackBuilder(const Curve& c, const Map& map) : c_(c), map_(map) {}

  // Fits the whole path into `tr` (pieces in order of u, closed ends joined, arc lengths, extrema, ranges).
  void build(AxisTrack& tr) {
    tr.closed_ = c_.closed();
    std::vector<double> cuts{c_.u_begin()};
    for (double k : c_.breakpoints()) cuts.push_back(k);
    cuts.push_back(c_.u_end());
    // start with at least 8 pieces over the whole path
    const int per = std::max(1, 8 / static_cast<int>(cuts.size() - 1));
    std::vector<double> us;
    for (size_t k = 0; k + 1 < cuts.size(); ++k)
      for (int i = 0; i < per; ++i) us.push_back(i == 0 ? cuts[k] : cuts[k] + (cuts[k + 1] - cuts[k]) * i / per);
    us.push_back(c_.u_end());

    const double zero[2] = {0.0, 0.0};
    Sample prev = sample(us[0], zero);
    for (size_t i = 1; i < us.size(); ++i) {
      Sample next = sample(us[i], prev.q);
      const bool at_cut = i + 1 < us.size() && std::binary_search(cuts.begin() + 1, cuts.end() - 1, us[i]);
      fit(prev, at_cut ? from_left(next) : next, 0, tr.pieces_);
      prev = next;
      take_end(prev, tr.pieces_.back());  // continuity of an unwrapped angle
    }
    auto& P = tr.pieces_;
    if (tr.closed_) tr.winding_ = map_.close(P.front().q_a, P.back().q_b);
    tr.finish();
  }

 private:
  static constexpr int N = kChebMaxDegree;
  static constexpr int kMaxDepth = 48;
  static constexpr long kMaxFits = 20'000'000;  // about 2 GB of pieces: beyond this the path is not machinable

  struct Sample {
    double u = 0;
    Vec2 p;
    double q[2] = {0, 0};
    double v = 0, aux = 0;  // speed |P'(u)|; the map's tolerance scale
  };

  std::string where(double u) const {
    CurvePoint p = c_.eval(u, 0);
    std::ostringstream os;
    os.precision(6);
    os << "path parameter " << u << " (" << Map::kFrame << "x = " << p.p.x * 1e3 << " mm, y = " << p.p.y * 1e3
       << " mm)";
    return os.str();
  }

  // Samples the path at u; an angle is unwrapped against `ref` (the coordinates of a nearby sample).
  Sample sample(double u, const double ref[2]) const {
    CurvePoint p = c_.eval(u, 1);
    if (!std::isfinite(p.p.x) || !std::isfinite(p.p.y)) throw InputError("the path is not finite at " + where(u));
    Sample s;
    s.u = u;
    s.p = p.p;
    s.v = norm(p.d1);
    if (!std::isfinite(s.v)) throw InputError("the path's tangent is not finite at " + where(u));
    if (!map_.coords(p.p, ref, s.q, s.aux)) throw InputError(std::string("the path ") + Map::kSingular + " at " + where(u));
    return s;
  }
  // The sample s at a breakpoint as the end of the piece before it: a curve whose parameter speed |P'| jumps at
  // the breakpoint (a curve of segments with one parameter unit each) has the speed of its left side there. A speed
  // that does not jump (beyond 1e-9 relative) is kept as it is, so that such paths are fitted as before, bit for bit.
  Sample from_left(const Sample& s) const {
    Sample l = s;
    const double v = norm(c_.eval(std::nextafter(s.u, -HUGE_VAL), 1).d1);
    if (std::isfinite(v) && std::abs(v - s.v) > 1e-9 * std::max(v, s.v)) l.v = v;
    return l;
  }
  // Sample s with its coordinates taken against `ref` again (an angle on the branch of ref).
  void rewrap(Sample& s, const double ref[2]) const { map_.coords(s.p, ref, s.q, s.aux); }
  static void take_end(Sample& s, const TrackPiece& pc) { s.q[0] = pc.q_b[0], s.q[1] = pc.q_b[1]; }

  // Fits [a, b] with degree 8, then 16; on failure splits and recurses, left first, so pieces come out in order
  // of u. b's coordinates are taken again against the sample next to it; the caller takes the piece's q_b as the
  // next piece's start.
  void fit(const Sample& a, const Sample& b, int depth, std::vector<TrackPiece>& out) {
    if (++fits_ > kMaxFits)
      throw InputError("cannot resolve the path near " + where(a.u) + ": it needs more than " +
                       std::to_string(kMaxFits) + " pieces (" + Map::kRough + ")");
    const auto& tp = cheb_points();  // t_j from +1 (j = 0) to -1 (j = N)
    std::array<Sample, N + 1> s;
    s[N] = a;
    const double mid = 0.5 * (a.u + b.u), half = 0.5 * (b.u - a.u);
    bool ok = true;
    for (int j = N - 2; j >= 2; j -= 2) {
      s[j] = sample(mid + half * tp[j], s[j + 2].q);
      ok = ok && map_.smooth(s[j + 2].q, s[j].q);
    }
    s[0] = b;
    rewrap(s[0], s[2].q);
    ok = ok && map_.smooth(s[2].q, s[0].q);

    TrackPiece pc;
    if (ok && try_fit(s, 2, a, half, pc)) return accept(pc, a, s[0], out);
    ok = true;
    for (int j = N - 1; j >= 1; j -= 2) {
      s[j] = sample(mid + half * tp[j], s[j + 1].q);
      ok = ok && map_.smooth(s[j + 1].q, s[j].q) && map_.smooth(s[j - 1].q, s[j].q);
    }
    if (ok && try_fit(s, 1, a, half, pc)) return accept(pc, a, s[0], out);
    if (depth >= kMaxDepth || !(mid > a.u && mid < b.u))
      throw InputError("cannot resolve the path near " + where(mid) + ": " + Map::kRough + " there");
    const Sample& m = s[N / 2];  // t = 0 is the midpoint
    fit(a, m, depth + 1, out);
    Sample m2 = m;
    take_end(m2, out.back());
    fit(m2, s[0], depth + 1, out);
  }

  // Fits the samples s[0], s[stride], ... (stride 2: degree 8; stride 1: degree 16). True when converged to the
  // map's tolerances (the arc length's: 1e-14 relative).
  bool try_fit(const std::array<Sample, N + 1>& s, int stride, const Sample& a, double half, TrackPiece& pc) const {
    const int n = N / stride;
    std::array<double, N + 1> f0{}, f1{}, fv{};
    double span[2] = {0, 0}, mv = 0, aux_min = a.aux;
    for (int j = 0; j <= n; ++j) {
      const Sample& x = s[j * stride];
      aux_min = std::min(aux_min, x.aux);
      f0[j] = x.q[0] - a.q[0];
      f1[j] = x.q[1] - a.q[1];
      fv[j] = x.v * half;
      span[0] = std::max(span[0], std::abs(f0[j]));
      span[1] = std::max(span[1], std::abs(f1[j]));
      mv = std::max(mv, fv[j]);
    }
    double tol[2];
    map_.tolerances(a.q, span, aux_min, tol);
    const double tol_v = 1e-14 * mv + 1e-300;
    // a fit that has not converged is refused on its last two coefficients, before the others are formed
    if (cheb_fit_tail(f0.data(), n) > tol[0] || cheb_fit_tail(f1.data(), n) > tol[1] ||
        cheb_fit_tail(fv.data(), n) > tol_v)
      return false;
    pc.Q[0] = cheb_fit(f0.data(), n);
    pc.Q[1] = cheb_fit(f1.data(), n);
    pc.V = cheb_fit(fv.data(), n);
    if (cheb_tail(pc.Q[0]) > tol[0] || cheb_tail(pc.Q[1]) > tol[1] || cheb_tail(pc.V) > tol_v) return false;
    cheb_chop(pc.Q[0], tol[0]);
    cheb_chop(pc.Q[1], tol[1]);
    cheb_chop(pc.V, tol_v);
    return true;
  }

  static void accept(TrackPiece& pc, const Sample& a, const Sample& b, std::vector<TrackPiece>& out) {
    pc.ua = a.u;
    pc.ub = b.u;
    for (int k = 0; k < 2; ++k) {
      pc.q_a[k] = a.q[k];
      pc.q_b[k] = b.q[k];
      pc.dQ[k] = pc.Q[k].derivative();
    }
    pc.S = pc.V.integral();
    pc.len = pc.S(1.0);
    out.push_back(pc);
  }

  const Curve& c_;
  const Map& map_;
  long fits_ = 0;
};

// The track of `path` through the axis map `map`. Throws InputError when the path is not finite, meets a
// singularity of the map, or cannot be resolved.
template <class Map>
void build_axis_track(const Curve& path, const Map& map, AxisTrack& out) {
  TrackBuilder<Map>(path, map).build(out);
}

}  // namespace polarcam
