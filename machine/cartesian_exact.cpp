#include "machine/cartesian_exact.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "cam/error.hpp"

namespace polarcam {

namespace {

struct Cursor {
  int dir = 0;
  bool has = false;
  double level = 0, t = 0;  // pending crossing
  double lo = 0, flo = 0;   // bracket start and the axis value there minus the pending level
  double prev[2] = {0, 0};  // the axis's last two crossings on this sub-interval (for the starting guess)
  int nprev = 0;
};

// g, g' and g'' at t in one Clenshaw pass.
inline void eval3(const Cheb& g, double t, double& f, double& f1, double& f2) {
  const double tt = 2.0 * t;
  double b1 = 0, b2 = 0, d1 = 0, d2 = 0, e1 = 0, e2 = 0;
  for (int k = g.deg; k >= 1; --k) {
    const double b0 = g.c[k] + tt * b1 - b2, d0 = 2.0 * b1 + tt * d1 - d2, e0 = 4.0 * d1 + tt * e1 - e2;
    b2 = b1;
    b1 = b0;
    d2 = d1;
    d1 = d0;
    e2 = e1;
    e1 = e0;
  }
  f = g.c[0] + t * b1 - b2;
  f1 = b1 + t * d1 - d2;
  f2 = 2.0 * d1 + t * e1 - e2;
}

// Root of g(t) = y in [lo, hi] with flo = g(lo) - y and fhi = g(hi) - y of opposite signs (or flo == 0): Newton
// from `guess` with bisection as the safeguard; the last Newton step is taken without a further evaluation once
// its own error g'' dt^2 / (2 g') is below 1e-15 (t is on [-1, 1]). The polar digitizer solves the same way.
double solve(const Cheb& g, double y, double lo, double hi, double flo, double fhi, double guess) {
  if (flo == 0.0) return lo;
  double t = guess;
  if (!(t > lo && t < hi)) {
    t = (fhi != flo) ? lo - flo * (hi - lo) / (fhi - flo) : 0.5 * (lo + hi);
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
  }
  for (int it = 0; it < 200; ++it) {
    double f, f1, f2;
    eval3(g, t, f, f1, f2);
    f -= y;
    if (f == 0.0) return t;
    if ((f < 0) == (flo < 0)) {
      lo = t;
      flo = f;
    } else {
      hi = t;
    }
    double tn = 0.5 * (lo + hi);
    if (f1 != 0.0) {
      const double dt = -f / f1;
      if (t + dt > lo && t + dt < hi) {
        tn = t + dt;
        if (std::abs(dt) <= 1e-4 && std::abs(f2 * dt * dt) <= 2e-15 * std::abs(f1)) return tn;
      }
    }
    if (hi - lo <= 4e-16) return tn;
    t = tn;
  }
  return t;
}

}  // namespace

CartesianResult step_exact(const CartesianTrack& tr, double blu, const SpeedProfile& profile, StepSink* sink) {
  if (!(blu > 0.0) || !std::isfinite(blu)) throw InputError("the Cartesian resolution must be a positive length");
  CartesianResult res;
  res.closed = tr.closed();
  res.path_length_m = tr.length();
  res.duration_s = profile.time_at(tr.length());
  res.duration_ns = std::llround(res.duration_s * 1e9);
  cartesian_node(tr.max_abs_coordinate(), blu);  // range check
  check_step_budget(tr.length(), blu);

  const auto& P = tr.pieces();
  const auto& E = tr.extrema();
  int64_t node[2] = {cartesian_node(P.front().x_a, blu), cartesian_node(P.front().y_a, blu)};
  CartesianTally tally(res, sink);
  tally.start_at(node);
  int64_t last_ns = 0;
  auto emit = [&](int axis, int dir, double s) {
    int64_t ns = std::llround(profile.time_at(s) * 1e9);
    if (ns < last_ns) ns = last_ns;
    last_ns = ns;
    tally.step(axis, dir, ns);
  };

  std::vector<double> ts;
  for (const XYPiece& pc : P) {
    Cheb g[2] = {pc.X, pc.Y};
    g[0].scale(1.0 / blu);
    g[1].scale(1.0 / blu);
    const double base[2] = {pc.x_a / blu, pc.y_a / blu};
    const double end[2] = {pc.x_b / blu, pc.y_b / blu};
    ts.assign(1, -1.0);
    for (uint32_t k = pc.ext_begin; k < pc.ext_end; ++k) ts.push_back(E[k]);
    ts.push_back(1.0);
    double fprev[2] = {base[0], base[1]};
    for (size_t k = 0; k + 1 < ts.size(); ++k) {
      const double tl = ts[k], th = ts[k + 1];
      double fend[2];
      for (int a = 0; a < 2; ++a) fend[a] = (k + 2 == ts.size()) ? end[a] : base[a] + g[a](th);
      Cursor cur[2];
      auto advance = [&](int a) {
        Cursor& c = cur[a];
        c.has = false;
        if (c.dir == 0) return;
        const double level = static_cast<double>(node[a]) + (c.dir > 0 ? 0.5 : -0.5);
        if (c.dir > 0 ? !(fend[a] >= level) : !(fend[a] < level)) return;
        const double flo = c.flo - level;
        const double guess = c.nprev == 2 ? 2.0 * c.prev[0] - c.prev[1] : -2.0;  // linear extrapolation
        c.t = solve(g[a], level - base[a], c.lo, th, flo, fend[a] - level, guess);
        c.level = level;
        c.has = true;
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
        emit(a, c.dir, pc.s0 + pc.S(c.t));
        node[a] += c.dir;
        c.lo = c.t;
        c.flo = c.level;  // the axis stands at the level it just crossed
        c.prev[1] = c.prev[0];
        c.prev[0] = c.t;
        if (c.nprev < 2) ++c.nprev;
        advance(a);
      }
      fprev[0] = fend[0];
      fprev[1] = fend[1];
    }
  }
  tally.finish();
  if (tally.node()[0] != node[0] || tally.node()[1] != node[1])
    throw std::logic_error("internal error: the Cartesian tally lost a step");
  if (res.closed && !res.returns_to_start)
    throw std::logic_error("internal error: a closed path did not return to its start node");
  return res;
}

}  // namespace polarcam
