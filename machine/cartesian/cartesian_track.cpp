#include "machine/cartesian/cartesian_track.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "cam/error.hpp"
#include "digitizer/polar_track.hpp"  // cheb_sign_changes

namespace polarcam {
namespace {

constexpr int N = kChebMaxDegree;
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr int kMaxDepth = 48;

std::string where(const Curve& c, double u) {
  CurvePoint p = c.eval(u, 0);
  std::ostringstream os;
  os.precision(6);
  os << "path parameter " << u << " (x = " << p.p.x * 1e3 << " mm, y = " << p.p.y * 1e3 << " mm)";
  return os.str();
}

struct Sample {
  double u;
  double x, y, v;  // position and speed |P'(u)|
};

class Builder {
 public:
  explicit Builder(const Curve& c) : c_(c) {}

  Sample sample(double u) const {
    CurvePoint p = c_.eval(u, 1);
    Sample s{u, p.p.x, p.p.y, norm(p.d1)};
    if (!std::isfinite(s.x) || !std::isfinite(s.y)) throw InputError("the path is not finite at " + where(c_, u));
    if (!std::isfinite(s.v)) throw InputError("the path's tangent is not finite at " + where(c_, u));
    return s;
  }

  // Fits [a, b] with degree 8, then 16; on failure halves and recurses, left first (pieces come out in order).
  void fit(const Sample& a, const Sample& b, int depth, std::vector<XYPiece>& out) const {
    const auto& tp = cheb_points();  // t_j from +1 (j = 0) to -1 (j = N)
    std::array<Sample, N + 1> s;
    s[N] = a;
    s[0] = b;
    const double mid = 0.5 * (a.u + b.u), half = 0.5 * (b.u - a.u);
    for (int j = N - 2; j >= 2; j -= 2) s[j] = sample(mid + half * tp[j]);
    XYPiece pc;
    if (try_fit(s, 2, a, half, pc)) return accept(pc, a, b, out);
    for (int j = N - 1; j >= 1; j -= 2) s[j] = sample(mid + half * tp[j]);
    if (try_fit(s, 1, a, half, pc)) return accept(pc, a, b, out);
    if (depth >= kMaxDepth) throw InputError("cannot resolve the path near " + where(c_, mid) + ": it is not smooth there");
    const Sample& m = s[N / 2];  // t = 0 is the midpoint
    fit(a, m, depth + 1, out);
    fit(m, b, depth + 1, out);
  }

 private:
  static bool try_fit(const std::array<Sample, N + 1>& s, int stride, const Sample& a, double half, XYPiece& pc) {
    const int n = N / stride;
    std::array<double, N + 1> fx{}, fy{}, fv{};
    double mx = 0, my = 0, mv = 0;
    for (int j = 0; j <= n; ++j) {
      const Sample& q = s[j * stride];
      fx[j] = q.x - a.x;
      fy[j] = q.y - a.y;
      fv[j] = q.v * half;
      mx = std::max(mx, std::abs(fx[j]));
      my = std::max(my, std::abs(fy[j]));
      mv = std::max(mv, fv[j]);
    }
    pc.X = cheb_fit(fx.data(), n);
    pc.Y = cheb_fit(fy.data(), n);
    pc.V = cheb_fit(fv.data(), n);
    // the scale of a coordinate is its size on the piece, not its distance from the origin alone
    const double tol_x = 16 * kEps * (std::abs(a.x) + mx + my) + 1e-300;
    const double tol_y = 16 * kEps * (std::abs(a.y) + mx + my) + 1e-300;
    const double tol_v = 1e-14 * mv + 1e-300;
    if (cheb_tail(pc.X) > tol_x || cheb_tail(pc.Y) > tol_y || cheb_tail(pc.V) > tol_v) return false;
    cheb_chop(pc.X, tol_x);
    cheb_chop(pc.Y, tol_y);
    cheb_chop(pc.V, tol_v);
    return true;
  }

  static void accept(XYPiece& pc, const Sample& a, const Sample& b, std::vector<XYPiece>& out) {
    pc.ua = a.u;
    pc.ub = b.u;
    pc.x_a = a.x;
    pc.x_b = b.x;
    pc.y_a = a.y;
    pc.y_b = b.y;
    pc.S = pc.V.integral();
    pc.len = pc.S(1.0);
    out.push_back(pc);
  }

  const Curve& c_;
};

}  // namespace

CartesianTrack CartesianTrack::build(const Curve& c) {
  CartesianTrack tr;
  tr.closed_ = c.closed();
  Builder b(c);
  std::vector<double> cuts{c.u_begin()};
  for (double k : c.breakpoints()) cuts.push_back(k);
  cuts.push_back(c.u_end());
  const int per = std::max(1, 8 / static_cast<int>(cuts.size() - 1));  // at least 8 pieces to start with
  std::vector<double> us;
  for (size_t k = 0; k + 1 < cuts.size(); ++k)
    for (int i = 0; i < per; ++i) us.push_back(i == 0 ? cuts[k] : cuts[k] + (cuts[k + 1] - cuts[k]) * i / per);
  us.push_back(c.u_end());

  Sample prev = b.sample(us[0]);
  for (size_t i = 1; i < us.size(); ++i) {
    Sample next = b.sample(us[i]);
    b.fit(prev, next, 0, tr.pieces_);
    prev = next;
  }
  auto& P = tr.pieces_;
  if (tr.closed_) {  // a closed path ends exactly where it starts
    P.back().x_b = P.front().x_a;
    P.back().y_b = P.front().y_a;
  }

  tr.bounds_ = Bounds{P.front().x_a, P.front().x_a, P.front().y_a, P.front().y_a};
  double s = 0.0, comp = 0.0;  // compensated summation of the arc length
  std::vector<double> roots;
  for (auto& pc : P) {
    pc.s0 = s;
    double y = pc.len - comp, t = s + y;
    comp = (t - s) - y;
    s = t;
    roots.clear();
    cheb_sign_changes(pc.X.derivative(), roots);
    cheb_sign_changes(pc.Y.derivative(), roots);
    std::sort(roots.begin(), roots.end());
    pc.ext_begin = static_cast<uint32_t>(tr.extrema_.size());
    double last = -1.0;
    for (double r : roots) {
      if (r <= -1.0 + 1e-14 || r >= 1.0 - 1e-14 || r - last <= 1e-14) continue;
      tr.extrema_.push_back(r);
      last = r;
    }
    pc.ext_end = static_cast<uint32_t>(tr.extrema_.size());
    auto see = [&](double px, double py) {
      tr.max_abs_ = std::max({tr.max_abs_, std::abs(px), std::abs(py)});
      Bounds& bx = tr.bounds_;
      bx.x0 = std::min(bx.x0, px), bx.x1 = std::max(bx.x1, px), bx.y0 = std::min(bx.y0, py), bx.y1 = std::max(bx.y1, py);
    };
    see(pc.x_a, pc.y_a);
    see(pc.x_b, pc.y_b);
    for (uint32_t k = pc.ext_begin; k < pc.ext_end; ++k) {
      const double te = tr.extrema_[k];
      see(pc.x_a + pc.X(te), pc.y_a + pc.Y(te));
    }
  }
  tr.length_ = s;
  return tr;
}

}  // namespace polarcam
