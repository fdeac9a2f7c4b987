#include "metrics/f1.hpp"

#include <cmath>
#include <stdexcept>

namespace polarcam {

std::vector<Vec2> segment_points(const Curve& path, int n) {
  if (n < 1) throw std::invalid_argument("segment_points: n must be positive");
  std::vector<Vec2> pts;
  pts.reserve(static_cast<size_t>(n) + 1);
  const double u0 = path.u_begin(), u1 = path.u_end();
  for (int i = 0; i <= n; ++i) pts.push_back(path.eval(i == n ? u1 : u0 + (u1 - u0) * i / n, 0).p);
  return pts;
}

namespace {

// a.x b.y - a.y b.x to within an ulp or two (Kahan's compensated 2 x 2 determinant): for a chord nearly in line
// with the pole the plain formula keeps only the digits that do not cancel.
double cross_exact(Vec2 a, Vec2 b) {
  const double w = a.y * b.x;
  const double e = std::fma(-a.y, b.x, w);
  const double f = std::fma(a.x, b.y, -w);
  return f + e;
}

}  // namespace

double chord_inverse_radius_integral(Vec2 a, Vec2 b) {
  // P(s) = a + s d, s in [0, 1]: dtheta = c ds / |P|^2 with c = cross(a, d) constant, so the integral of
  // dtheta / r is c times the integral of |P|^-3, which is (P.d / r)/c^2 at the ends: (b.d/|b| - a.d/|a|) / c.
  const Vec2 d = b - a;
  const double ra = norm(a), rb = norm(b), ld = norm(d), c = cross_exact(a, b);  // = cross(a, d)
  if (ra == 0.0 || rb == 0.0 || ld == 0.0) return 0.0;
  const double ca = dot(a, d) / (ra * ld), cb = dot(b, d) / (rb * ld);
  // nearly radial chords (c small) lose everything to cancellation in cb - ca; there
  // cb - ca = (sa^2 - sb^2) / (ca + cb) with s = c / (r |d|), which is exact and stable
  if ((ca > 0) == (cb > 0) && std::abs(ca + cb) > 1.0)
    return std::abs(c * (1.0 / (ra * ra) - 1.0 / (rb * rb)) / (ld * (ca + cb)));
  return std::abs(ld * (cb - ca) / c);
}

namespace {

void add_terms(F1Value& v, double nr, double nt, double penalised_nt, bool penalise) {
  const double t = penalise ? penalised_nt : nt;
  v.F_sum += std::abs(nr + t);
  v.F_dif += std::abs(nr - t);
  ++v.segments_used;
}

void finish(F1Value& v) { v.F1 = v.F_sum > 0.0 ? v.F_dif / v.F_sum : 0.0; }

}  // namespace

F1Value f1_chords(const std::vector<Vec2>& p, Vec2 pole, double dr, double dtheta) {
  F1Value v;
  const double k = dr / (dtheta * dtheta);
  for (size_t i = 0; i + 1 < p.size(); ++i) {
    const Vec2 a = p[i] - pole, b = p[i + 1] - pole;
    const double nr = std::abs(norm(b) - norm(a)) / dr;
    const double nt = std::abs(std::atan2(cross(a, b), dot(a, b))) / dtheta;
    if (nr == 0.0 || nt == 0.0) continue;  // the listing skips these chords
    const bool pen = nr >= nt;
    add_terms(v, nr, nt, pen ? k * chord_inverse_radius_integral(a, b) : nt, pen);
  }
  finish(v);
  return v;
}

F1Value f1_chords(const std::vector<Vec2>& points, double dr, double dtheta) {
  return f1_chords(points, Vec2{0, 0}, dr, dtheta);
}

F1Value f1_counts(const std::vector<Vec2>& p, const std::vector<long long>& radial,
                  const std::vector<long long>& angular, double dr, double dtheta) {
  if (radial.size() + 1 != p.size() || angular.size() + 1 != p.size())
    throw std::invalid_argument("f1_counts: one count per segment");
  F1Value v;
  const double K = dr / dtheta;
  for (size_t i = 0; i < radial.size(); ++i) {
    const double nr = static_cast<double>(radial[i]), nt = static_cast<double>(angular[i]);
    const double rm = norm(0.5 * (p[i] + p[i + 1]));
    const bool pen = nr > nt && rm > 0.0;
    add_terms(v, nr, nt, pen ? nt * K / rm : nt, pen);
  }
  finish(v);
  return v;
}

}  // namespace polarcam
