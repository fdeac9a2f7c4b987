#include "machine/servo/contour.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "cam/error.hpp"

namespace polarcam::servo {
namespace {

constexpr double kSide = 50e-3;  // m: the test paths' size

// Distance covered at time tau along a leg of length L at speed f with linear ramps of duration ta at both ends
// (ta = 0: constant speed); the leg lasts L/f + ta.
double along(double L, double f, double ta, double tau) {
  if (ta <= 0.0) return std::clamp(f * tau, 0.0, L);
  const double dur = L / f + ta;
  if (tau <= 0.0) return 0.0;
  if (tau >= dur) return L;
  if (tau < ta) return 0.5 * f * tau * tau / ta;
  if (tau > dur - ta) {
    const double r = dur - tau;
    return L - 0.5 * f * r * r / ta;
  }
  return 0.5 * f * ta + f * (tau - ta);
}

}  // namespace

const char* to_string(TestPath p) {
  switch (p) {
    case TestPath::square: return "square";
    case TestPath::diamond: return "diamond";
    case TestPath::circle: return "circle";
  }
  return "square";
}

TestPath parse_test_path(const std::string& name) {
  if (name == "square") return TestPath::square;
  if (name == "diamond") return TestPath::diamond;
  if (name == "circle") return TestPath::circle;
  throw InputError("'" + name + "' is not a test path: give square, diamond or circle", "--path");
}

Reference test_path(TestPath path, double feed, double T, double ramp, double hold) {
  if (!(std::isfinite(feed) && feed > 0.0 && feed <= 10.0)) throw InputError("must be a feed above 0 and at most 10 m/s", "--feed");
  if (!(std::isfinite(ramp) && ramp >= 0.0 && ramp <= 10.0)) throw InputError("must be from 0 to 10 s", "--ramp");
  Reference r;
  r.T = T;
  const double L = kSide;
  std::vector<std::pair<double, double>> v;  // vertices of a polygon
  double leg = 0.0, total = 0.0;
  if (path == TestPath::square) {
    v = {{0, 0}, {L, 0}, {L, L}, {0, L}, {0, 0}};
    leg = L;
  } else if (path == TestPath::diamond) {
    v = {{-L, 0}, {0, L}, {L, 0}, {0, -L}, {-L, 0}};
    leg = L * std::sqrt(2.0);
  }
  const double circumference = 2.0 * std::numbers::pi * L;
  if (path == TestPath::circle) {
    if (ramp > 0.0 && circumference / feed < ramp) throw InputError("is longer than the circle takes at this feed", "--ramp");
    total = circumference / feed + ramp;
  } else {
    if (ramp > 0.0 && leg / feed < ramp) throw InputError("is longer than a leg takes at this feed", "--ramp");
    total = (leg / feed + ramp) * 4.0;
  }
  const double span = total + hold;
  if (span / T > 5e7) throw InputError("makes a reference of more than 5e7 samples", "--feed");
  const size_t n = static_cast<size_t>(std::ceil(span / T - 1e-9)) + 1;
  r.q[0].resize(n);
  r.q[1].resize(n);
  const double leg_time = leg / feed + ramp;
  for (size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * T;
    double x, y;
    if (path == TestPath::circle) {
      const double phi = along(circumference, feed, ramp, t) / L;  // Eq. 4.104, 4.105 with w t = s/R
      x = L * std::sin(phi);
      y = L * std::cos(phi);
    } else {
      const size_t i = std::min<size_t>(3, static_cast<size_t>(std::max(0.0, std::floor(t / leg_time))));
      const double d = along(leg, feed, ramp, t - static_cast<double>(i) * leg_time) / leg;
      x = v[i].first + (v[i + 1].first - v[i].first) * d;
      y = v[i].second + (v[i + 1].second - v[i].second) * d;
    }
    r.q[0][k] = x;
    r.q[1][k] = y;
  }
  return r;
}

SplineSegment hermite_segment(const double p0[2], const double v0[2], const double p1[2], const double v1[2], double dt) {
  // B*^-1 of Eq. 4.135: rows multiply r(t0), r'(t0) dt, r(t1), r'(t1) dt; columns give s^3, s^2, s, 1
  static const double Binv[4][4] = {{2, -3, 0, 1}, {1, -2, 1, 0}, {-2, 3, 0, 0}, {1, -1, 0, 0}};
  SplineSegment g;
  g.dt = dt;
  for (int i = 0; i < 2; ++i) {
    const double R[4] = {p0[i], v0[i] * dt, p1[i], v1[i] * dt};
    for (int c = 0; c < 4; ++c) {
      double sum = 0.0;
      for (int k = 0; k < 4; ++k) sum += R[k] * Binv[k][c];
      g.A[i][c] = sum;
    }
  }
  return g;
}

SplinedPath test_path_with_splines(TestPath path, double feed, double T, int segments, double reach, double hold) {
  if (path == TestPath::circle) throw InputError("the circle has no corners to blend: give square or diamond", "--corner");
  if (!(std::isfinite(feed) && feed > 0.0 && feed <= 10.0)) throw InputError("must be a feed above 0 and at most 10 m/s", "--feed");
  if (segments != 1 && segments != 2) throw InputError("must be spline (one segment) or spline2 (two)", "--corner");
  const double L = kSide;
  std::vector<std::array<double, 2>> v =
      path == TestPath::square ? std::vector<std::array<double, 2>>{{0, 0}, {L, 0}, {L, L}, {0, L}, {0, 0}}
                               : std::vector<std::array<double, 2>>{{-L, 0}, {0, L}, {L, 0}, {0, -L}, {-L, 0}};
  const double leg = std::hypot(v[1][0] - v[0][0], v[1][1] - v[0][1]);
  if (!(reach > 0.0 && reach < leg / 2)) throw InputError("the corner blend must be shorter than half a leg", "--corner");
  // pieces in time: a straight piece (from, to, duration) or a spline segment
  struct Piece {
    bool spline = false;
    double from[2], to[2];
    SplineSegment seg;
    double dur = 0.0;
  };
  std::vector<Piece> pieces;
  SplinedPath out;
  auto unit = [&](int i) {
    const double dx = v[i + 1][0] - v[i][0], dy = v[i + 1][1] - v[i][1];
    return std::array<double, 2>{dx / leg, dy / leg};
  };
  double start[2] = {v[0][0], v[0][1]};
  for (int i = 0; i < 4; ++i) {
    const auto u = unit(i);
    const bool corner_after = i < 3;  // the path starts and ends at rest at its first vertex
    const double end[2] = {v[i + 1][0] - (corner_after ? reach * u[0] : 0.0), v[i + 1][1] - (corner_after ? reach * u[1] : 0.0)};
    Piece s;
    s.from[0] = start[0];
    s.from[1] = start[1];
    s.to[0] = end[0];
    s.to[1] = end[1];
    s.dur = std::hypot(end[0] - start[0], end[1] - start[1]) / feed;
    pieces.push_back(s);
    if (!corner_after) break;
    const auto w = unit(i + 1);
    const double c[2] = {v[i + 1][0], v[i + 1][1]};
    const double pf[2] = {c[0] + reach * w[0], c[1] + reach * w[1]};
    const double vs[2] = {feed * u[0], feed * u[1]}, vf[2] = {feed * w[0], feed * w[1]};
    const double dt = 2.0 * reach / feed;
    CornerSpline cs;
    cs.corner[0] = c[0];
    cs.corner[1] = c[1];
    if (segments == 1) {
      cs.segments.push_back(hermite_segment(end, vs, pf, vf, dt));
    } else {
      const double pm[2] = {c[0] + 0.01 * ((end[0] + pf[0]) / 2 - c[0]), c[1] + 0.01 * ((end[1] + pf[1]) / 2 - c[1])};
      const double vm[2] = {(vs[0] + vf[0]) / 2, (vs[1] + vf[1]) / 2};
      cs.segments.push_back(hermite_segment(end, vs, pm, vm, dt / 2));
      cs.segments.push_back(hermite_segment(pm, vm, pf, vf, dt / 2));
    }
    for (const SplineSegment& g : cs.segments) {
      Piece p;
      p.spline = true;
      p.seg = g;
      p.dur = g.dt;
      pieces.push_back(p);
    }
    out.corners.push_back(cs);
    start[0] = pf[0];
    start[1] = pf[1];
  }
  double total = 0.0;
  for (const Piece& p : pieces) total += p.dur;
  const size_t n = static_cast<size_t>(std::ceil((total + hold) / T - 1e-9)) + 1;
  Reference& r = out.reference;
  r.T = T;
  r.q[0].resize(n);
  r.q[1].resize(n);
  size_t i = 0;
  double t0 = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * T;
    while (i + 1 < pieces.size() && t > t0 + pieces[i].dur) {
      t0 += pieces[i].dur;
      ++i;
    }
    const Piece& p = pieces[i];
    const double s = std::clamp((t - t0) / p.dur, 0.0, 1.0);
    for (int a = 0; a < 2; ++a) {
      if (p.spline) {
        const double* A = p.seg.A[a];
        r.q[a][k] = ((A[0] * s + A[1]) * s + A[2]) * s + A[3];
      } else {
        r.q[a][k] = p.from[a] + (p.to[a] - p.from[a]) * s;
      }
    }
  }
  return out;
}

double signed_distance(const std::vector<double>& x, const std::vector<double>& y, size_t i0, size_t i1, double px,
                       double py, double& at) {
  double best = -1.0, sign_best = 1.0;
  at = static_cast<double>(i0);
  for (size_t i = i0; i < i1; ++i) {
    const double dx = x[i + 1] - x[i], dy = y[i + 1] - y[i];
    const double l2 = dx * dx + dy * dy;
    if (l2 == 0.0) {
      if (best < 0.0) {  // a stationary reference: the distance to its point
        best = std::hypot(px - x[i], py - y[i]);
        at = static_cast<double>(i);
      }
      continue;
    }
    const double u = std::clamp(((px - x[i]) * dx + (py - y[i]) * dy) / l2, 0.0, 1.0);
    const double qx = x[i] + u * dx - px, qy = y[i] + u * dy - py;
    const double d = std::hypot(qx, qy);
    if (best < 0.0 || d < best) {
      best = d;
      at = static_cast<double>(i) + u;
      // right of the travel: the cross product of the direction and (p - q) is negative
      const double cross = dx * (-qy) - dy * (-qx);
      sign_best = cross > 0.0 ? -1.0 : 1.0;
    }
  }
  return best < 0.0 ? 0.0 : best * sign_best;
}

ContourResult run_contour(const Drives& drives, const Reference& ref, const ServoOptions& opt) {
  const size_t n = ref.q[0].size();
  if (n < 2 || ref.q[1].size() != n) throw InputError("the reference needs at least two samples of both axes");
  if (drives.axis[0].params.T != ref.T) throw InputError("the reference is not sampled at the drives' sample period");
  if (!(opt.tolerance > 0.0 && std::isfinite(opt.tolerance))) throw InputError("must be a positive length", "--tolerance");
  ContourResult c;
  c.polar = drives.polar;
  c.T = ref.T;
  c.tolerance = opt.tolerance;
  c.t.resize(n);
  for (size_t k = 0; k < n; ++k) c.t[k] = static_cast<double>(k) * ref.T;
  double settle[2];
  for (int a = 0; a < 2; ++a) {
    const AxisDrive& d = drives.axis[a];
    const double per = d.per_count();
    std::vector<double> counts(n);
    for (size_t k = 0; k < n; ++k) {
      counts[k] = ref.q[a][k] / per;
      if (!std::isfinite(counts[k]) || std::abs(counts[k]) > 1e15)
        throw InputError("the reference of axis " + d.name + " is beyond 1e15 encoder counts");
    }
    ServoAxis axis(d.params, counts[0]);
    settle[a] = axis.model().settling_time;
    c.ref[a] = ref.q[a];
    c.act[a].resize(n);
    c.current[a].resize(n);
    for (size_t k = 0; k < n; ++k) {
      const ServoSample s = axis.step(counts[k], opt.cutting_torque[a]);
      c.act[a][k] = s.X_a * per;
      c.current[a][k] = s.I_a;
      c.max_current[a] = std::max(c.max_current[a], std::abs(s.I_a));
    }
  }
  // the tool point
  for (int i = 0; i < 2; ++i) {
    c.ref_xy[i].resize(n);
    c.act_xy[i].resize(n);
  }
  for (size_t k = 0; k < n; ++k) {
    if (c.polar) {
      c.ref_xy[0][k] = c.ref[0][k] * std::cos(c.ref[1][k]);
      c.ref_xy[1][k] = c.ref[0][k] * std::sin(c.ref[1][k]);
      c.act_xy[0][k] = c.act[0][k] * std::cos(c.act[1][k]);
      c.act_xy[1][k] = c.act[0][k] * std::sin(c.act[1][k]);
    } else {
      for (int i = 0; i < 2; ++i) {
        c.ref_xy[i][k] = c.ref[i][k];
        c.act_xy[i][k] = c.act[i][k];
      }
    }
  }
  c.s.assign(n, 0.0);
  for (size_t k = 1; k < n; ++k)
    c.s[k] = c.s[k - 1] + std::hypot(c.ref_xy[0][k] - c.ref_xy[0][k - 1], c.ref_xy[1][k] - c.ref_xy[1][k - 1]);
  // contour error: the actual point against the reference path from 1 s (the axes lag by the following error over
  // the speed, some 15 ms for J. Peng's drives) behind to 50 samples ahead
  const size_t back = static_cast<size_t>(std::ceil(1.0 / ref.T)), ahead = 50;
  c.e_c.resize(n);
  std::vector<double> s_near(n);
  for (size_t k = 0; k < n; ++k) {
    const size_t i0 = k > back ? k - back : 0, i1 = std::min(n - 1, k + ahead);
    double at = 0.0;
    c.e_c[k] = signed_distance(c.ref_xy[0], c.ref_xy[1], i0, i1, c.act_xy[0][k], c.act_xy[1][k], at);
    const size_t i = std::min(n - 2, static_cast<size_t>(at));
    s_near[k] = c.s[i] + (at - static_cast<double>(i)) * (c.s[i + 1] - c.s[i]);
    if (std::abs(c.e_c[k]) > c.max_abs_contour_error) {
      c.max_abs_contour_error = std::abs(c.e_c[k]);
      c.max_at_t = c.t[k];
      c.max_at_s = s_near[k];
      c.max_at_x = c.act_xy[0][k];
      c.max_at_y = c.act_xy[1][k];
    }
  }
  for (size_t k = 0; k < n;) {
    if (std::abs(c.e_c[k]) <= opt.tolerance) {
      ++k;
      continue;
    }
    Interval iv;
    iv.t_begin = c.t[k];
    iv.s_begin = s_near[k];
    for (; k < n && std::abs(c.e_c[k]) > opt.tolerance; ++k) {
      iv.t_end = c.t[k];
      iv.s_end = s_near[k];
      iv.max_abs_error = std::max(iv.max_abs_error, std::abs(c.e_c[k]));
    }
    c.out_of_tolerance.push_back(iv);
  }
  // following error at steady speed
  const size_t w = 100;
  for (int a = 0; a < 2; ++a) {
    const std::vector<double>& q = c.ref[a];
    const double jitter = 1.5 * ref.quantum[a] / (static_cast<double>(w) * ref.T);
    size_t best_begin = 0, best_end = 0;
    double best_speed = 0.0;
    size_t k = w;
    while (k < n) {
      const double v0 = (q[k] - q[k - w]) / (static_cast<double>(w) * ref.T);
      if (!(std::abs(v0) > jitter)) {
        ++k;
        continue;
      }
      size_t j = k + 1;
      double sum = v0;
      while (j < n) {
        const double v = (q[j] - q[j - w]) / (static_cast<double>(w) * ref.T);
        if (std::abs(v - v0) > std::max(1e-3 * std::abs(v0), jitter)) break;
        sum += v;
        ++j;
      }
      if (j - k > best_end - best_begin) {
        best_begin = k;
        best_end = j;
        best_speed = sum / static_cast<double>(j - k);
      }
      k = j;
    }
    const size_t skip = static_cast<size_t>(std::ceil(settle[a] / ref.T));
    SteadyError& st = c.steady[a];
    if (best_end > best_begin + skip + w) {
      const size_t b = best_begin + skip;
      double sum = 0.0;
      for (size_t i = b; i < best_end; ++i) sum += c.ref[a][i] - c.act[a][i];
      st.found = true;
      st.speed = best_speed;
      st.error = sum / static_cast<double>(best_end - b) * (best_speed > 0.0 ? 1.0 : -1.0);
      st.error_counts = st.error / drives.axis[a].per_count();
      st.t_begin = c.t[b];
      st.t_end = c.t[best_end - 1];
    }
  }
  if (c.steady[0].found && c.steady[1].found) {
    const double b = std::max(c.steady[0].t_begin, c.steady[1].t_begin);
    const double e = std::min(c.steady[0].t_end, c.steady[1].t_end);
    if (e > b) {
      const size_t kb = static_cast<size_t>(std::llround(b / ref.T)), ke = static_cast<size_t>(std::llround(e / ref.T));
      double sum = 0.0;
      for (size_t k = kb; k <= ke; ++k) sum += c.e_c[k];
      c.steady_contour_found = true;
      c.steady_contour_error = sum / static_cast<double>(ke - kb + 1);
    }
  }
  return c;
}

}  // namespace polarcam::servo
