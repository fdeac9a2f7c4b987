#include "machine/player/run_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace polarcam {
namespace {

constexpr int kBasis = 4;                     // offset, interval, add, add2
constexpr double kTwo32 = 4294967296.0;
constexpr double kMargin = 1.0 / (1 << 20);   // ticks kept clear of every band edge (rounding to 2^-32 ticks)
constexpr int kMaxExchanges = 64;

// The run's position after k steps, P(k) = sum_j c_j phi_j(k), in the binomial basis phi_j(k) = C(k, j): C(k,1)
// intervals of I, C(k,2) adds A, C(k,3) second adds B (docs/controller-protocol.md).
inline double phi(uint32_t k, int j) {
  const double x = k;
  switch (j) {
    case 0: return 1.0;
    case 1: return x;
    case 2: return x * (x - 1) / 2;
    default: return x * (x - 1) * (x - 2) / 6;
  }
}

// A fit of P to the bands of steps 1..n: some coefficients fixed, the others solved.
struct Fit {
  std::array<bool, kBasis> free{true, true, true, true};
  std::array<double, kBasis> c{0, 0, 0, 0};  // ticks
  std::vector<uint32_t> ref;                 // Remez reference (steps) and the band each touches (+1 upper)
  std::vector<int> sig;
  double viol = 0;                           // max over steps of the distance outside the band (<= 0: inside)
};

// The bands of the steps after the clock, computed when asked for: the search touches only the steps of the run
// it finds (and one more), never the whole limit, so a proposal costs time in proportion to its length.
class Bands {
 public:
  Bands(const StepWindow* w, i128 clock)
      : w_(w), base_(static_cast<int64_t>(clock >> kFracBits)),
        frac_(static_cast<double>(static_cast<uint32_t>(clock & 0xffffffffu)) / kTwo32) {}
  // step k fires at tick floor(clock + P): lo <= clock + P < hi + 1
  double L(uint32_t k) const { return static_cast<double>(w_[k - 1].lo - base_) - frac_ + kMargin; }
  double U(uint32_t k) const { return static_cast<double>(w_[k - 1].hi + 1 - base_) - frac_ - kMargin; }

  static double eval(const Fit& f, uint32_t k) {
    double p = 0;
    for (int j = 0; j < kBasis; ++j)
      if (f.c[j] != 0) p += f.c[j] * phi(k, j);
    return p;
  }
  bool inside(const Fit& f, uint32_t k) const {
    const double p = eval(f, k);
    return p >= L(k) && p <= U(k);
  }
  // Largest violation over steps 1..n, its step and side (+1 above the band).
  double worst(const Fit& f, uint32_t n, uint32_t* at, int* side) const {
    double v = -INFINITY;
    for (uint32_t k = 1; k <= n; ++k) {
      const double p = eval(f, k);
      const double up = p - U(k), down = L(k) - p;
      if (up > v) {
        v = up;
        *at = k;
        *side = 1;
      }
      if (down > v) {
        v = down;
        *at = k;
        *side = -1;
      }
    }
    return v;
  }

  // Minimax fit over steps 1..n of the free coefficients; returns the largest violation of the fit it leaves in
  // f (<= 0: every step inside its band). `warm`: start from f's reference.
  double minimax(Fit& f, uint32_t n, bool warm) const {
    int fb[kBasis], m = 0;
    for (int j = 0; j < kBasis; ++j)
      if (f.free[j]) fb[m++] = j;
    uint32_t at = 0;
    int side = 0;
    if (m == 0) return f.viol = worst(f, n, &at, &side);
    if (n < static_cast<uint32_t>(m) + 1) return interpolate(f, n, fb, m);
    const int N = m + 1;
    if (!warm || f.ref.size() != static_cast<size_t>(N)) {
      f.ref.assign(N, 0);
      f.sig.assign(N, 0);
      for (int i = 0; i < N; ++i) f.ref[i] = 1 + static_cast<uint32_t>(std::llround(static_cast<double>(n - 1) * i / (N - 1)));
      Fit a = f, b = f;
      for (int i = 0; i < N; ++i) {
        a.sig[i] = i % 2 ? 1 : -1;
        b.sig[i] = -a.sig[i];
      }
      double la = 0, lb = 0;
      const bool oa = level(a, fb, m, n, &la), ob = level(b, fb, m, n, &lb);
      if (!oa && !ob) return f.viol = INFINITY;
      f = oa && (!ob || la >= lb) ? a : b;
    }
    double lev = 0;
    if (!level(f, fb, m, n, &lev)) return f.viol = INFINITY;
    Fit best = f;
    best.viol = INFINITY;
    for (int it = 0; it < kMaxExchanges; ++it) {
      const double v = worst(f, n, &at, &side);
      if (v < best.viol) {
        best = f;
        best.viol = v;
      }
      if (v <= lev + 1e-9) break;  // levelled: optimal
      // exchange: `at` enters the reference, keeping the sides alternating
      std::vector<uint32_t>& r = f.ref;
      std::vector<int>& g = f.sig;
      if (std::find(r.begin(), r.end(), at) != r.end()) break;  // rounding: no progress possible
      int i = 0;
      while (i < N && r[i] < at) ++i;
      if (i == 0) {
        if (g[0] != side) {
          std::copy_backward(r.begin(), r.end() - 1, r.end());
          std::copy_backward(g.begin(), g.end() - 1, g.end());
        }
        r[0] = at;
        g[0] = side;
      } else if (i == N) {
        if (g[N - 1] != side) {
          std::copy(r.begin() + 1, r.end(), r.begin());
          std::copy(g.begin() + 1, g.end(), g.begin());
        }
        r[N - 1] = at;
        g[N - 1] = side;
      } else {
        r[g[i - 1] == side ? i - 1 : i] = at;
      }
      if (!level(f, fb, m, n, &lev)) break;
    }
    f = best;
    return f.viol;
  }

 private:
  const StepWindow* w_;
  int64_t base_;
  double frac_;

  double fixed_part(const Fit& f, uint32_t k) const {
    double p = 0;
    for (int j = 0; j < kBasis; ++j)
      if (!f.free[j] && f.c[j] != 0) p += f.c[j] * phi(k, j);
    return p;
  }

  // Solves the levelled equations on the reference: P(r_i) = U + e on upper touches, L - e on lower ones.
  bool level(Fit& f, const int* fb, int m, uint32_t n, double* e) const {
    const int N = m + 1;
    double A[kBasis + 1][kBasis + 2];
    double scale[kBasis];
    for (int q = 0; q < m; ++q) scale[q] = std::max(1.0, phi(n, fb[q]));
    for (int i = 0; i < N; ++i) {
      const uint32_t k = f.ref[i];
      for (int q = 0; q < m; ++q) A[i][q] = phi(k, fb[q]) / scale[q];
      A[i][m] = -f.sig[i];
      A[i][N] = (f.sig[i] > 0 ? U(k) : L(k)) - fixed_part(f, k);
    }
    if (!gauss(A, N)) return false;
    for (int q = 0; q < m; ++q) f.c[fb[q]] = A[q][N] / scale[q];
    *e = A[m][N];
    return true;
  }

  // Fewer steps than a reference needs: the band centres interpolated by the lowest orders (interval first,
  // then add, add2, offset).
  double interpolate(Fit& f, uint32_t n, const int* fb, int m) const {
    static constexpr int kOrder[kBasis] = {1, 2, 3, 0};
    int use[kBasis], u = 0;
    for (int j : kOrder)
      for (int q = 0; q < m; ++q)
        if (fb[q] == j && u < static_cast<int>(n)) use[u++] = j;
    for (int q = 0; q < m; ++q) f.c[fb[q]] = 0;
    double A[kBasis + 1][kBasis + 2];
    for (int i = 0; i < u; ++i) {
      const uint32_t k = static_cast<uint32_t>(i) + 1;
      for (int q = 0; q < u; ++q) A[i][q] = phi(k, use[q]);
      A[i][u] = 0.5 * (L(k) + U(k)) - fixed_part(f, k);
    }
    if (!gauss(A, u)) return f.viol = INFINITY;
    for (int q = 0; q < u; ++q) f.c[use[q]] = A[q][u];
    f.ref.clear();
    uint32_t at = 0;
    int side = 0;
    return f.viol = worst(f, n, &at, &side);
  }

  static bool gauss(double (&A)[kBasis + 1][kBasis + 2], int N) {
    for (int i = 0; i < N; ++i) {
      int p = i;
      for (int r = i + 1; r < N; ++r)
        if (std::fabs(A[r][i]) > std::fabs(A[p][i])) p = r;
      if (!(std::fabs(A[p][i]) > 1e-12)) return false;
      if (p != i)
        for (int c = 0; c <= N; ++c) std::swap(A[i][c], A[p][c]);
      for (int r = 0; r < N; ++r) {
        if (r == i) continue;
        const double q = A[r][i] / A[i][i];
        if (q == 0) continue;
        for (int c = i; c <= N; ++c) A[r][c] -= q * A[i][c];
      }
    }
    for (int i = 0; i < N; ++i) A[i][N] /= A[i][i];
    return true;
  }
};

// The candidate for a coefficient: the prediction plus the delta to `centre` rounded to a multiple of 2^shift
// (the wire sends the multiple), within the range the wire allows.
int64_t candidate(double centre_ticks, int64_t predicted, int shift) {
  const double limit = std::ldexp(1.0, 62);
  const double target = std::clamp(centre_ticks * kTwo32, -limit, limit);
  const i128 unit = static_cast<i128>(1) << shift;
  const double m = std::nearbyint((target - static_cast<double>(predicted)) / static_cast<double>(unit));
  const i128 v = static_cast<i128>(predicted) + static_cast<i128>(m) * unit;
  const i128 lim = static_cast<i128>(1) << 62;
  return static_cast<int64_t>(std::clamp(v, -lim, lim));
}

}  // namespace

RunProposal propose_run(const StepWindow* w, uint32_t limit, i128 clock, const RunRef& ref, const RunShape& shape) {
  RunProposal out;
  if (limit == 0) return out;
  const Bands bands(w, clock);
  // grow the run while a cubic still fits every band
  Fit cur;
  cur.free[0] = shape.offset;
  cur.free[3] = shape.cubic;
  uint32_t n = 0;
  for (uint32_t k = 1; k <= limit; ++k) {
    if (n > 0 && bands.inside(cur, k)) {
      n = k;
      continue;
    }
    Fit trial = cur;
    if (bands.minimax(trial, k, true) <= 0) {
      cur = std::move(trial);
      n = k;
    } else {
      break;
    }
  }
  if (n == 0) {  // cannot happen with non-empty windows; let the caller's exact fallback place the step
    out.count = 1;
    return out;
  }
  // fix the coefficients from the highest order down, each to the shortest value on the wire
  const int64_t predicted[kBasis] = {0, ref.interval, ref.add, ref.add2};
  int64_t chosen[kBasis] = {0, 0, 0, 0};
  for (int j = kBasis - 1; j >= 0; --j) {
    if (!cur.free[j]) continue;  // not in this shape: zero
    const double centre = cur.c[j];
    auto test = [&](int64_t v, Fit& t) {
      t = cur;
      t.free[j] = false;
      t.c[j] = static_cast<double>(v) / kTwo32;
      return bands.minimax(t, n, false) <= 0;
    };
    Fit t;
    if (test(predicted[j], t)) {  // the prediction itself: nothing to send but a zero
      chosen[j] = predicted[j];
      cur = std::move(t);
      continue;
    }
    // the coarsest even power of two (as the wire's shifts) whose multiple fits; feasibility shrinks with the
    // shift, so bisect
    int a = 0, b = 15;
    Fit fa;
    bool have_a = false;
    while (a < b) {
      const int mid = (a + b + 1) / 2;
      Fit tm;
      if (test(candidate(centre, predicted[j], 2 * mid), tm)) {
        a = mid;
        fa = std::move(tm);
        have_a = true;
      } else {
        b = mid - 1;
      }
    }
    chosen[j] = candidate(centre, predicted[j], 2 * a);
    if (!have_a) test(chosen[j], fa);  // the finest grid: kept even if rounding spoils it (checked exactly later)
    cur = std::move(fa);
  }
  out.count = n;
  out.offset = chosen[0];
  out.interval = chosen[1];
  out.add = chosen[2];
  out.add2 = chosen[3];
  return out;
}

}  // namespace polarcam
