#include "metrics/track_area.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace polarcam {
namespace {

// Product of two series: T_i T_j = (T_{i+j} + T_{|i-j|}) / 2.
template <class A, class B>
LongCheb multiply(const A& a, int da, const B& b, int db) {
  LongCheb p;
  p.deg = std::min(da + db, kLongChebMaxDegree);
  for (int i = 0; i <= da; ++i) {
    if (a[i] == 0.0) continue;
    for (int j = 0; j <= db; ++j) {
      const double v = 0.5 * a[i] * b[j];
      if (i + j <= kLongChebMaxDegree) p.c[i + j] += v;
      p.c[i > j ? i - j : j - i] += v;
    }
  }
  return p;
}

// Integral from -1 (value zero there).
LongCheb integrate(const LongCheb& f) {
  LongCheb I;
  const int n = std::min(f.deg + 1, kLongChebMaxDegree);
  I.deg = n;
  std::array<double, kLongChebMaxDegree + 3> a{};
  for (int k = 0; k <= f.deg; ++k) a[k] = f.c[k];
  for (int k = 1; k <= n; ++k) I.c[k] = (a[k - 1] - a[k + 1]) / (2.0 * k);
  I.c[1] += 0.5 * a[0];
  double v = 0.0;
  for (int k = 1; k <= n; ++k) v += (k % 2 ? -1.0 : 1.0) * I.c[k];
  I.c[0] = -v;
  return I;
}

void chop(LongCheb& s) {
  double scale = 0.0;
  for (int k = 0; k <= s.deg; ++k) scale += std::abs(s.c[k]);
  const double tol = 0.125 * std::numeric_limits<double>::epsilon() * scale;
  double acc = 0.0;
  while (s.deg > 0 && acc + std::abs(s.c[s.deg]) <= tol) {
    acc += std::abs(s.c[s.deg]);
    s.c[s.deg] = 0.0;
    --s.deg;
  }
}

}  // namespace

void sector_area_series(const sweep::TrackView& track, std::vector<LongCheb>& out) {
  out.clear();
  out.reserve(track.pieces.size());
  const bool polar = track.geo == sweep::Geometry::polar;
  for (const sweep::PieceView& p : track.pieces) {
    const Cheb& H = *p.H;
    const Cheb dG = p.G->derivative();
    LongCheb f;
    if (polar) {
      // (r^2 - r_a^2) / 2 = R (2 r_a + R) / 2
      std::array<double, kChebMaxDegree + 1> twice{};  // (2 r_a + R) / 2
      for (int k = 0; k <= H.deg; ++k) twice[k] = 0.5 * H.c[k];
      twice[0] += p.h_a;
      LongCheb q = multiply(H.c, H.deg, twice, H.deg);
      f = multiply(q.c, q.deg, dG.c, dG.deg);
    } else {
      f = multiply(H.c, H.deg, dG.c, dG.deg);  // (y - y_a) x'
    }
    LongCheb a = integrate(f);
    chop(a);
    out.push_back(a);
  }
}

std::vector<LongCheb> sector_area_series(const sweep::TrackView& track) {
  std::vector<LongCheb> out;
  sector_area_series(track, out);
  return out;
}

}  // namespace polarcam
