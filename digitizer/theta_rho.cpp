#include "digitizer/theta_rho.hpp"

#include <algorithm>
#include <array>
#include <cmath>

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


// Fills an axis track from a theta-rho polyline (the friend of AxisTrack that sets its pieces).
struct PolylineTrackFill {
  static void fill(AxisTrack& tr, const ThetaRhoPath& path, double c, double r_floor) {
    if (!std::isfinite(r_floor) || r_floor < 0.0) throw InputError("the timing radius at the centre must be a finite length >= 0");
    const auto& v = path.vertices();
    tr.pieces_.clear();
    tr.extrema_.clear();
    tr.closed_ = path.closed();
    tr.pieces_.reserve(v.size() - 1);  // one piece a segment as a rule: no doubling of the largest array
    for (size_t k = 0; k + 1 < v.size(); ++k) {
      const ThetaRho& a = v[k];
      const ThetaRho& b = v[k + 1];
      const double dth = b.theta - a.theta, drho = b.rho - a.rho;
      if (drho == 0.0 && dth != 0.0 && a.rho == 0.0 && r_floor == 0.0)
        throw InputError("the arm turns at the centre without moving the ball; give the machine's "
                         "max_angular_speed so that the turn can be timed",
                         "segment " + std::to_string(k + 1) + " (points " + std::to_string(k + 1) + "-" +
                             std::to_string(k + 2) + ")");
      // split where rho crosses r_floor: the timing length's rate has a kink there
      double fs[3] = {0.0, 1.0, 1.0};
      int nf = 2;
      if (r_floor > 0.0 && drho != 0.0) {
        const double f = (r_floor - a.rho) / drho;
        if (f > 0.0 && f < 1.0) fs[1] = f, nf = 3;
      }
      for (int i = 0; i + 1 < nf; ++i) segment(tr.pieces_, a, b, static_cast<double>(k), c, r_floor, fs[i], fs[i + 1], 0);
    }
    if (tr.closed_) tr.winding_ = static_cast<int>(std::nearbyint((v.back().theta - v.front().theta) / PolarMap::kTwoPi));
    tr.finish();
  }

 private:
  // Axis coordinates at fraction f of the segment a -> b (evaluated the same way at both ends of every piece,
  // so consecutive pieces share their end points exactly; f = 0 and f = 1 give the vertices themselves).
  static void coords(const ThetaRho& a, const ThetaRho& b, double c, double f, double q[2]) {
    const double th = f == 1.0 ? b.theta : a.theta + (b.theta - a.theta) * f;
    const double rho = f == 1.0 ? b.rho : a.rho + (b.rho - a.rho) * f;
    q[0] = rho + c * th;
    q[1] = th;
  }

  static void segment(std::vector<TrackPiece>& out, const ThetaRho& a, const ThetaRho& b, double u0, double c,
                      double r_floor, double fa, double fb, int depth) {
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
      segment(out, a, b, u0, c, r_floor, fa, fm, depth + 1);
      segment(out, a, b, u0, c, r_floor, fm, fb, depth + 1);
      return;
    }
    if (!ok) cheb_chop(pc.V, tol_v);
    pc.ua = u0 + fa;
    pc.ub = u0 + fb;
    coords(a, b, c, fa, pc.q_a);
    coords(a, b, c, fb, pc.q_b);
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
    out.push_back(pc);
  }
};

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
