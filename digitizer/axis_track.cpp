#include "digitizer/axis_track.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace polarcam {

namespace {

constexpr int kMaxSamples = 48;

// The sample abscissae -cos(pi i / M) (ends exactly -1 and 1) of every M up to kMaxSamples, computed once.
const std::array<double, kMaxSamples + 1>& chebyshev_nodes(int M) {
  static const auto table = [] {
    std::array<std::array<double, kMaxSamples + 1>, kMaxSamples + 1> t{};
    for (int m = 1; m <= kMaxSamples; ++m) {
      for (int i = 0; i <= m; ++i) t[static_cast<size_t>(m)][static_cast<size_t>(i)] = -std::cos(std::numbers::pi * i / m);
      t[static_cast<size_t>(m)][0] = -1.0;
      t[static_cast<size_t>(m)][static_cast<size_t>(m)] = 1.0;
    }
    return t;
  }();
  return table[static_cast<size_t>(M)];
}

}  // namespace

void cheb_sign_changes(const Cheb& d, std::vector<double>& out) {
  if (d.deg == 0 || d.max_abs() == 0.0) return;  // a constant has no sign change (theta-rho segments: every piece)
  {
    // |d - c_0| <= sum_{k >= 1} |c_k| on [-1, 1]: where c_0 outweighs it with room for the rounding of an
    // evaluation, d keeps the sign of c_0 everywhere, and every sample and search below would find it so
    double tail = 0.0, sum = std::abs(d.c[0]);
    for (int k = 1; k <= d.deg; ++k) tail += std::abs(d.c[k]);
    sum += tail;
    if (std::abs(d.c[0]) - tail > 16.0 * (d.deg + 1) * std::numeric_limits<double>::epsilon() * sum) return;
  }
  // a degree-d series has at most d - 1 turning points: sample it four times as densely
  const int M = std::min(kMaxSamples, std::max(8, 4 * d.deg));
  const std::array<double, kMaxSamples + 1>& t = chebyshev_nodes(M);
  std::array<double, kMaxSamples + 1> g;
  // d at the M + 1 nodes, four Clenshaw recurrences side by side (the same operations as d(t) for each: the same
  // values, without waiting on one recurrence's chain)
  for (int i0 = 0; i0 <= M; i0 += 4) {
    double x[4], b1[4] = {0.0, 0.0, 0.0, 0.0}, b2[4] = {0.0, 0.0, 0.0, 0.0};
    for (int j = 0; j < 4; ++j) x[j] = t[static_cast<size_t>(std::min(i0 + j, M))];
    for (int k = d.deg; k >= 1; --k)
      for (int j = 0; j < 4; ++j) {
        const double b0 = d.c[k] + 2.0 * x[j] * b1[j] - b2[j];
        b2[j] = b1[j];
        b1[j] = b0;
      }
    for (int j = 0; j < 4 && i0 + j <= M; ++j) g[static_cast<size_t>(i0 + j)] = d.c[0] + x[j] * b1[j] - b2[j];
  }
  // A bound on |d'| on [-1, 1] (|T_k'| <= k^2) and on the rounding of an evaluation: they let a dip's search stop
  // as soon as the series is certainly positive (times its sign) over the rest of the bracket, where the search to
  // the end would have found no sign change either.
  double slope = 0.0, sum = 0.0;
  for (int k = 0; k <= d.deg; ++k) {
    slope += static_cast<double>(k) * k * std::abs(d.c[k]);
    sum += std::abs(d.c[k]);
  }
  const double rounding = 8.0 * (d.deg + 1) * std::numeric_limits<double>::epsilon() * sum;
  auto solve = [&](double lo, double hi, double glo, double ghi) { return cheb_solve(d, 0.0, lo, hi, glo, ghi); };
  for (int i = 0; i < M; ++i) {
    if (i > 0 && g[i] == 0.0) {
      if ((g[i - 1] < 0) != (g[i + 1] < 0) && g[i - 1] != 0.0 && g[i + 1] != 0.0) out.push_back(t[i]);
      continue;
    }
    if (g[i] != 0.0 && g[i + 1] != 0.0 && (g[i] < 0) != (g[i + 1] < 0)) {
      out.push_back(solve(t[i], t[i + 1], g[i], g[i + 1]));
      continue;
    }
    // a dip: |g| has a local minimum at an interior sample and the neighbours share its sign
    if (i > 0 && g[i] != 0.0 && (g[i - 1] < 0) == (g[i] < 0) && (g[i + 1] < 0) == (g[i] < 0) &&
        std::abs(g[i]) <= std::abs(g[i - 1]) && std::abs(g[i]) <= std::abs(g[i + 1])) {
      double sg = g[i] < 0 ? -1.0 : 1.0;
      // minimise sg * d on [t[i-1], t[i+1]] by golden section
      double lo = t[i - 1], hi = t[i + 1];
      const double gr = 0.6180339887498949;
      double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo), f1 = sg * d(x1), f2 = sg * d(x2);
      for (int it = 0; it < 80 && hi - lo > 1e-15; ++it) {
        if (std::min(f1, f2) - 2.0 * rounding - slope * (hi - lo) > 0.0) break;  // no sign change in [lo, hi]
        if (f1 < f2) {
          hi = x2;
          x2 = x1;
          f2 = f1;
          x1 = hi - gr * (hi - lo);
          f1 = sg * d(x1);
        } else {
          lo = x1;
          x1 = x2;
          f1 = f2;
          x2 = lo + gr * (hi - lo);
          f2 = sg * d(x2);
        }
      }
      double tm = f1 < f2 ? x1 : x2, fm = std::min(f1, f2);
      if (fm < 0.0) {
        out.push_back(solve(t[i - 1], tm, g[i - 1], sg * fm));
        out.push_back(solve(tm, t[i + 1], sg * fm, g[i + 1]));
      }
    }
  }
}

void AxisTrack::finish() {
  auto& P = pieces_;
  // arc length (compensated summation) and extrema
  double s = 0.0, comp = 0.0;
  std::vector<double> roots, roots1;
  for (auto& pc : P) {
    pc.s0 = s;
    double y = pc.len - comp, t = s + y;
    comp = (t - s) - y;
    s = t;
    roots.clear();
    cheb_sign_changes(pc.dQ[0], roots);
    const size_t n0 = roots.size();
    cheb_sign_changes(pc.dQ[1], roots);
    // the distinct roots in (-1, 1), sorted, appended to `to`
    auto keep = [](std::vector<double>::iterator a, std::vector<double>::iterator b, std::vector<double>& to) {
      std::sort(a, b);
      double last = -1.0;
      for (auto it = a; it != b; ++it) {
        const double r = *it;
        if (r <= -1.0 + 1e-14 || r >= 1.0 - 1e-14 || r - last <= 1e-14) continue;
        to.push_back(r);
        last = r;
      }
    };
    pc.turn_begin = static_cast<uint32_t>(turns_.size());
    roots1.assign(roots.begin() + static_cast<std::ptrdiff_t>(n0), roots.end());
    keep(roots1.begin(), roots1.end(), turns_);
    pc.turn_end = static_cast<uint32_t>(turns_.size());
    pc.ext_begin = static_cast<uint32_t>(extrema_.size());
    keep(roots.begin(), roots.end(), extrema_);
    pc.ext_end = static_cast<uint32_t>(extrema_.size());
  }
  length_ = s;

  // ranges of the axis coordinates: the ends of the pieces and the extrema
  for (int a = 0; a < 2; ++a) {
    qmin_[a] = {std::numeric_limits<double>::infinity(), 0, -1};
    qmax_[a] = {-std::numeric_limits<double>::infinity(), 0, -1};
  }
  auto consider = [&](size_t i, double t, const double q[2]) {
    for (int a = 0; a < 2; ++a) {
      if (q[a] < qmin_[a].value) qmin_[a] = {q[a], i, t};
      if (q[a] > qmax_[a].value) qmax_[a] = {q[a], i, t};
    }
  };
  for (size_t i = 0; i < P.size(); ++i) {
    consider(i, -1.0, P[i].q_a);
    for (uint32_t k = P[i].ext_begin; k < P[i].ext_end; ++k) {
      const double t = extrema_[k], q[2] = {this->q(0, i, t), this->q(1, i, t)};
      consider(i, t, q);
    }
  }
  consider(P.size() - 1, 1.0, P.back().q_b);
}

std::pair<size_t, double> AxisTrack::locate(double s) const {
  if (s <= 0.0) return {0, -1.0};
  if (s >= length_) return {pieces_.size() - 1, 1.0};
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), s, [](double v, const TrackPiece& p) { return v < p.s0; });
  size_t i = static_cast<size_t>(it - pieces_.begin()) - 1;
  const TrackPiece& p = pieces_[i];
  double target = s - p.s0;
  double t = cheb_solve(p.S, target, -1.0, 1.0, -target, p.len - target);
  return {i, t};
}

}  // namespace polarcam
