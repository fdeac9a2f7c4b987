#include "digitizer/polar_track.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "cam/error.hpp"

namespace polarcam {
namespace {

constexpr int N = kChebMaxDegree;
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kMaxDepth = 48;
constexpr long kMaxFits = 20'000'000;  // about 2 GB of pieces: beyond this the path is not something to machine
constexpr double kPoleDistance = 1e-9;  // m: a path this close to the pole passes through it

std::string where(const Curve& c, double u) {
  CurvePoint p = c.eval(u, 0);
  std::ostringstream os;
  os.precision(6);
  os << "path parameter " << u << " (machine x = " << p.p.x * 1e3 << " mm, y = " << p.p.y * 1e3 << " mm)";
  return os.str();
}

struct Sample {
  double u;
  Vec2 q;
  double r, th, v;  // distance and unwrapped angle from the pole, speed |Q'(u)|
};

class Builder {
 public:
  explicit Builder(const Curve& c) : c_(c), scale_(c.rounding_scale()) {}

  // Samples the path at u; the angle is unwrapped against `ref_th` (the angle of a nearby sample).
  Sample sample(double u, double ref_th) {
    CurvePoint p = c_.eval(u, 1);
    if (!std::isfinite(p.p.x) || !std::isfinite(p.p.y)) throw InputError("the path is not finite at " + where(c_, u));
    Sample s{u, p.p, std::sqrt(p.p.x * p.p.x + p.p.y * p.p.y), 0.0, norm(p.d1)};
    if (!std::isfinite(s.v)) throw InputError("the path's tangent is not finite at " + where(c_, u));
    if (s.r < kPoleDistance) throw InputError("the path passes through the machine pole at " + where(c_, u));
    s.th = unwrap(std::atan2(p.p.y, p.p.x), ref_th);
    return s;
  }
  static double unwrap(double a, double ref) { return a + kTwoPi * std::nearbyint((ref - a) / kTwoPi); }

  // Fits [a, b] with degree 8, then 16; on failure splits and recurses, left first, so pieces come out in order
  // of u. `b.th` is re-unwrapped here; the caller takes the piece's th_b as the next piece's start angle.
  void fit(const Sample& a, const Sample& b, int depth, std::vector<TrackPiece>& out) {
    if (++fits_ > kMaxFits)
      throw InputError("cannot resolve the path near " + where(c_, a.u) + ": it needs more than " +
                       std::to_string(kMaxFits) + " pieces (it passes too close to the machine pole or is not smooth)");
    const auto& tp = cheb_points();  // t_j from +1 (j = 0) to -1 (j = N)
    std::array<Sample, N + 1> s;
    s[N] = a;
    const double mid = 0.5 * (a.u + b.u), half = 0.5 * (b.u - a.u);
    constexpr double kJump = 0.25 * std::numbers::pi;
    bool ok = true;
    for (int j = N - 2; j >= 2; j -= 2) {
      s[j] = sample(mid + half * tp[j], s[j + 2].th);
      ok = ok && std::abs(s[j].th - s[j + 2].th) <= kJump;
    }
    s[0] = b;
    s[0].th = unwrap(std::atan2(b.q.y, b.q.x), s[2].th);
    ok = ok && std::abs(s[0].th - s[2].th) <= kJump;

    TrackPiece pc;
    if (ok && try_fit(s, 2, a, half, pc)) return accept(pc, a, s[0], out);
    ok = true;
    for (int j = N - 1; j >= 1; j -= 2) {
      s[j] = sample(mid + half * tp[j], s[j + 1].th);
      ok = ok && std::abs(s[j].th - s[j + 1].th) <= kJump && std::abs(s[j].th - s[j - 1].th) <= kJump;
    }
    if (ok && try_fit(s, 1, a, half, pc)) return accept(pc, a, s[0], out);
    if (depth >= kMaxDepth || !(mid > a.u && mid < b.u))
      throw InputError("cannot resolve the path near " + where(c_, mid) +
                       ": it passes too close to the machine pole or is not smooth there");
    const Sample& m = s[N / 2];  // t = 0 is the midpoint
    fit(a, m, depth + 1, out);
    Sample m2 = m;
    m2.th = out.back().th_b;  // continuity of the unwrapped angle
    fit(m2, s[0], depth + 1, out);
  }

 private:
  // Fits the samples s[0], s[stride], ... (stride 2: degree 8; stride 1: degree 16). True when converged.
  // Tolerances are a few units in the last place of the numbers r and theta come from: r itself and, for a
  // placed path, the pole distance and tool radius (rounding_scale), which dominate near the pole.
  bool try_fit(const std::array<Sample, N + 1>& s, int stride, const Sample& a, double half, TrackPiece& pc) const {
    const int n = N / stride;
    std::array<double, N + 1> fr{}, ft{}, fv{};
    double mr = 0, mt = 0, mv = 0, rmin = a.r;
    for (int j = 0; j <= n; ++j) {
      const Sample& x = s[j * stride];
      rmin = std::min(rmin, x.r);
      fr[j] = x.r - a.r;
      ft[j] = x.th - a.th;
      fv[j] = x.v * half;
      mr = std::max(mr, std::abs(fr[j]));
      mt = std::max(mt, std::abs(ft[j]));
      mv = std::max(mv, fv[j]);
    }
    pc.R = cheb_fit(fr.data(), n);
    pc.Th = cheb_fit(ft.data(), n);
    pc.V = cheb_fit(fv.data(), n);
    const double tol_r = 16 * kEps * (std::abs(a.r) + mr + scale_) + 1e-300;
    const double tol_t = 16 * kEps * (std::abs(a.th) + mt + 1.0 + scale_ / rmin) + 1e-300;
    const double tol_v = 1e-14 * mv + 1e-300;
    if (cheb_tail(pc.R) > tol_r || cheb_tail(pc.Th) > tol_t || cheb_tail(pc.V) > tol_v) return false;
    cheb_chop(pc.R, tol_r);
    cheb_chop(pc.Th, tol_t);
    cheb_chop(pc.V, tol_v);
    return true;
  }

  static void accept(TrackPiece& pc, const Sample& a, const Sample& b, std::vector<TrackPiece>& out) {
    pc.ua = a.u;
    pc.ub = b.u;
    pc.r_a = a.r;
    pc.r_b = b.r;
    pc.th_a = a.th;
    pc.th_b = b.th;
    pc.dR = pc.R.derivative();
    pc.dTh = pc.Th.derivative();
    pc.S = pc.V.integral();
    pc.len = pc.S(1.0);
    out.push_back(pc);
  }

  const Curve& c_;
  double scale_;
  long fits_ = 0;
};

}  // namespace

void cheb_sign_changes(const Cheb& d, std::vector<double>& out) {
  if (d.max_abs() == 0.0) return;
  constexpr int kMaxSamples = 48;
  // a degree-d series has at most d - 1 turning points: sample it four times as densely
  const int M = std::min(kMaxSamples, std::max(8, 4 * d.deg));
  std::array<double, kMaxSamples + 1> t, g;
  for (int i = 0; i <= M; ++i) {
    t[i] = -std::cos(std::numbers::pi * i / M);
    g[i] = d(t[i]);
  }
  t[0] = -1.0;
  t[M] = 1.0;
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
      // minimise sg * d on [t[i-1], t[i+1]] by Newton on d' = 0 with golden fallback
      double lo = t[i - 1], hi = t[i + 1];
      const double gr = 0.6180339887498949;
      double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo), f1 = sg * d(x1), f2 = sg * d(x2);
      for (int it = 0; it < 80 && hi - lo > 1e-15; ++it) {
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

PolarTrack PolarTrack::build(const Curve& c) {
  PolarTrack tr;
  tr.closed_ = c.closed();
  Builder b(c);
  std::vector<double> cuts{c.u_begin()};
  for (double k : c.breakpoints()) cuts.push_back(k);
  cuts.push_back(c.u_end());
  // start with at least 8 pieces over the whole path
  const int per = std::max(1, 8 / static_cast<int>(cuts.size() - 1));
  std::vector<double> us;
  for (size_t k = 0; k + 1 < cuts.size(); ++k)
    for (int i = 0; i < per; ++i) us.push_back(i == 0 ? cuts[k] : cuts[k] + (cuts[k + 1] - cuts[k]) * i / per);
  us.push_back(c.u_end());

  Sample prev = b.sample(us[0], 0.0);
  for (size_t i = 1; i < us.size(); ++i) {
    Sample next = b.sample(us[i], prev.th);
    b.fit(prev, next, 0, tr.pieces_);
    prev = next;
    prev.th = tr.pieces_.back().th_b;
  }

  auto& P = tr.pieces_;
  if (tr.closed_) {
    // a closed path ends exactly where it starts: same r, theta advanced by whole turns
    double turns = std::nearbyint((P.back().th_b - P.front().th_a) / kTwoPi);
    tr.winding_ = static_cast<int>(turns);
    P.back().r_b = P.front().r_a;
    P.back().th_b = P.front().th_a + kTwoPi * turns;
  }

  // arc length (compensated summation) and extrema
  double s = 0.0, comp = 0.0;
  std::vector<double> roots;
  for (auto& pc : P) {
    pc.s0 = s;
    double y = pc.len - comp, t = s + y;
    comp = (t - s) - y;
    s = t;
    roots.clear();
    cheb_sign_changes(pc.dR, roots);
    cheb_sign_changes(pc.dTh, roots);
    std::sort(roots.begin(), roots.end());
    pc.ext_begin = static_cast<uint32_t>(tr.extrema_.size());
    double last = -1.0;
    for (double r : roots) {
      if (r <= -1.0 + 1e-14 || r >= 1.0 - 1e-14 || r - last <= 1e-14) continue;
      tr.extrema_.push_back(r);
      last = r;
    }
    pc.ext_end = static_cast<uint32_t>(tr.extrema_.size());
  }
  tr.length_ = s;

  // ranges of r and theta
  tr.rmin_ = {std::numeric_limits<double>::infinity(), 0, -1};
  tr.rmax_ = {-std::numeric_limits<double>::infinity(), 0, -1};
  tr.thmin_ = tr.rmin_;
  tr.thmax_ = tr.rmax_;
  auto consider = [&](size_t i, double t, double r, double th) {
    if (r < tr.rmin_.value) tr.rmin_ = {r, i, t};
    if (r > tr.rmax_.value) tr.rmax_ = {r, i, t};
    if (th < tr.thmin_.value) tr.thmin_ = {th, i, t};
    if (th > tr.thmax_.value) tr.thmax_ = {th, i, t};
  };
  for (size_t i = 0; i < P.size(); ++i) {
    consider(i, -1.0, P[i].r_a, P[i].th_a);
    for (uint32_t k = P[i].ext_begin; k < P[i].ext_end; ++k) {
      double t = tr.extrema_[k];
      consider(i, t, tr.r(i, t), tr.theta(i, t));
    }
  }
  consider(P.size() - 1, 1.0, P.back().r_b, P.back().th_b);
  return tr;
}

std::pair<size_t, double> PolarTrack::locate(double s) const {
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
