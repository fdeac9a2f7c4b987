#include "metrics/error_metrics.hpp"

#include <algorithm>
#include <cmath>

#include "metrics/deviation.hpp"

namespace polarcam {

void ErrorMeters::reset(const Curve& path, const PolarTrack& track, const Grid& grid, int segments) {
  path_ = &path;
  track_ = &track;
  grid_ = grid;
  segments_ = std::max(1, segments);
  steps_.clear();
  area_.reset(track, grid);
}

ErrorMetrics ErrorMeters::finish(int64_t n0, int64_t m0) {
  ErrorMetrics out;
  out.area = area_.finish(n0, m0);  // checks that the staircase follows the path
  const double dr = grid_.dr, dth = grid_.dtheta;
  const Curve& c = *path_;
  const double u0 = c.u_begin(), u1 = c.u_end();
  auto at = [&](double n, double m) {
    const double rho = n * dr, phi = m * dth;
    return Vec2{rho * std::cos(phi), rho * std::sin(phi)};
  };
  auto reach = [&](double n) { return 3.0 * std::max(dr, n * dr * dth) + 1e-12; };

  const int ns = segments_;
  std::vector<long long> nr(static_cast<size_t>(ns), 0), nt(static_cast<size_t>(ns), 0);
  auto segment_of = [&](double u) {
    const int i = static_cast<int>(std::floor((u - u0) / (u1 - u0) * ns));
    return std::clamp(i, 0, ns - 1);
  };

  DeviationMeter dev(c);
  double n = static_cast<double>(n0), m = static_cast<double>(m0);
  dev.start(at(n, m), reach(n));
  for (uint8_t s : steps_) {
    const int axis = s & 1, dir = (s & 2) ? 1 : -1;
    StairPiece piece;
    if (axis == kAxisRadial) {
      piece.a = at(n, m);
      piece.b = at(n + dir, m);
    } else {
      piece.arc = true;
      piece.rho = n * dr;
      piece.phi0 = m * dth;
      piece.phi1 = (m + dir) * dth;
    }
    const double mn = axis == kAxisRadial ? n + 0.5 * dir : n;
    const double u = dev.piece(piece, reach(mn));  // foot point of the step's middle
    (axis == kAxisRadial ? nr : nt)[static_cast<size_t>(segment_of(u))] += 1;
    (axis == kAxisRadial ? n : m) += dir;
  }
  out.deviation_max_m = dev.max();
  out.deviation_at = dev.at();

  const double rmax = track_->r_max().value, K = dr / dth;
  out.deviation_eq41_m = rmax <= K ? dr : rmax * dth;
  out.segments = ns;
  const std::vector<Vec2> pts = segment_points(c, ns);
  out.f_counts = f1_counts(pts, nr, nt, dr, dth);
  out.f_chords = f1_chords(pts, dr, dth);
  steps_.clear();
  return out;
}

}  // namespace polarcam
