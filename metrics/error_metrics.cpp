#include "metrics/error_metrics.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <thread>

#include "metrics/deviation.hpp"

namespace polarcam {

void ErrorMeters::reset(const Curve& path, const PolarTrack& track, const Grid& grid, int segments) {
  path_ = &path;
  track_ = &track;
  grid_ = grid;
  segments_ = std::max(1, segments);
  segment_.reset(path.u_begin(), path.u_end(), segments_);
  steps_.clear();
  lane_.reset();
  dev_.reset();
  parallel_ = false;
  node_m_ = std::numeric_limits<double>::quiet_NaN();  // the grid may be another
  // the step as a pair hi + lo: 2 pi / N to about 1e-32 relative where a turn is N whole steps
  step_hi_ = grid_.dtheta;
  step_lo_ = 0.0;
  if (grid_.steps_per_rev > 0) {
    constexpr double kTwoPiHi = 6.283185307179586, kTwoPiLo = 2.4492935982947064e-16;
    const double N = static_cast<double>(grid_.steps_per_rev);
    step_hi_ = kTwoPiHi / N;
    step_lo_ = (std::fma(-step_hi_, N, kTwoPiHi) + kTwoPiLo) / N;
  }
  // a step of k: 1 - cos (as 2 sin^2 of the half angle, without cancellation) and sin
  tab_cos_.resize(kTurnBlock);
  tab_sin_.resize(kTurnBlock);
  for (int64_t k = 0; k < kTurnBlock; ++k) {
    const double phi = static_cast<double>(k) * step_hi_ + static_cast<double>(k) * step_lo_, h = std::sin(0.5 * phi);
    tab_cos_[k] = 2.0 * h * h;
    tab_sin_[k] = std::sin(phi);
  }
  block_ = std::numeric_limits<int64_t>::min();
  area_.reset(track, grid);
}

void ErrorMeters::turn(int64_t m, double& c, double& s) {
  const int64_t k = ((m % kTurnBlock) + kTurnBlock) % kTurnBlock;
  int64_t b = m - k;
  if (b != block_) {
    block_ = b;
    if (grid_.steps_per_rev > 0) {  // whole turns are exact
      const int64_t N = grid_.steps_per_rev;
      b = ((b % N) + N) % N;
    }
    // b (hi + lo) as p + e (p = b hi rounded, e its rounding error plus b lo), and cos, sin of p + e to first order
    const double bd = static_cast<double>(b), p = bd * step_hi_, e = std::fma(bd, step_hi_, -p) + bd * step_lo_;
    const double cp = std::cos(p), sp = std::sin(p);
    block_cos_ = cp - sp * e;
    block_sin_ = sp + cp * e;
  }
  // cos(B + K) = cos B - (cos B (1 - cos K) + sin B sin K): the bracket is small, so its rounding is too
  c = block_cos_ - (block_cos_ * tab_cos_[k] + block_sin_ * tab_sin_[k]);
  s = block_sin_ + (block_cos_ * tab_sin_[k] - block_sin_ * tab_cos_[k]);
}

double ErrorMeters::reach(double n) const { return 3.0 * std::max(grid_.dr, n * grid_.dr * grid_.dtheta) + 1e-12; }

void SegmentIndex::reset(double u0, double u1, int segments) {
  u0_ = u0;
  u1_ = u1;
  n_ = std::max(1, segments);
  first_.assign(static_cast<size_t>(n_), std::numeric_limits<double>::quiet_NaN());
  lo_ = hi_ = 0.0;
}

int SegmentIndex::formula(double u) const {
  const double x = std::floor((u - u0_) / (u1_ - u0_) * n_);
  if (!(x > 0.0)) return 0;  // (NaN too)
  return x >= n_ - 1 ? n_ - 1 : static_cast<int>(x);
}

namespace {
// doubles in the order of their values as integers (-0 and +0 both 0), and back
int64_t ordered(double x) {
  const auto i = std::bit_cast<int64_t>(x);
  return i >= 0 ? i : std::numeric_limits<int64_t>::min() - i;
}
double unordered(int64_t o) { return std::bit_cast<double>(o >= 0 ? o : std::numeric_limits<int64_t>::min() - o); }
}  // namespace

double SegmentIndex::first(int i) {
  double& f = first_[static_cast<size_t>(i)];
  if (f == f) return f;
  // between the path's ends: the formula is 0 at u0 and the last segment at u1
  int64_t lo = ordered(u0_), hi = ordered(u1_);  // formula(lo) < i <= formula(hi)
  while (hi - lo > 1) {
    const int64_t mid = lo + (hi - lo) / 2;
    if (formula(unordered(mid)) >= i)
      hi = mid;
    else
      lo = mid;
  }
  f = unordered(hi);
  return f;
}

int SegmentIndex::lookup(double u) {
  const int s = formula(u);
  if (!(u == u)) return s;  // (not kept)
  seg_ = s;
  lo_ = s == 0 ? -std::numeric_limits<double>::infinity() : first(s);
  hi_ = s + 1 < n_ ? first(s + 1) : std::numeric_limits<double>::infinity();
  return s;
}

void ErrorMeters::start_following(int64_t n0, int64_t m0) {
  foot_ = std::numeric_limits<double>::quiet_NaN();
  dev_ = std::make_unique<DeviationMeter>(*path_);
  dev_->set_bounds(dev_bounds_);
  if (segments_ > 1) {  // a step's segment is its foot's: near a segment's bounds the foot is found, not estimated
    const double u0 = path_->u_begin(), u1 = path_->u_end();
    std::vector<double> bounds;
    for (int i = 0; i <= segments_; ++i) bounds.push_back(u0 + (u1 - u0) * i / segments_);
    dev_->set_exact_near(std::move(bounds));
  }
  nr_.assign(static_cast<size_t>(segments_), 0);
  nt_.assign(static_cast<size_t>(segments_), 0);
  n_ = static_cast<double>(n0);
  m_ = static_cast<double>(m0);
  dev_->start(node(n_, m_), reach(n_));
}

void ErrorMeters::follow_all(const uint8_t* steps, size_t count) {
  for (size_t i = 0; i < count; ++i) follow(steps[i] & 1, (steps[i] & 2) ? 1 : -1);
}

void ErrorMeters::area_all(const uint8_t* steps, size_t count) {
  for (size_t i = 0; i < count; ++i) area_.record(steps[i] & 1, (steps[i] & 2) ? 1 : -1);
}

void ErrorMeters::follow(int axis, int dir) {
  const double dr = grid_.dr, dth = grid_.dtheta;
  double& n = n_;
  double& m = m_;
  StairPiece piece;
  if (axis == kAxisRadial) {
    piece.a = node(n, m);
    piece.b = node(n + dir, m);
  } else {
    piece.arc = true;
    piece.rho = n * dr;
    piece.phi0 = m * dth;
    piece.phi1 = (m + dir) * dth;
    piece.b = node(n, m + dir);  // the next radial step shares its angle's cosine and sine
  }
  const double mn = axis == kAxisRadial ? n + 0.5 * dir : n;
  const DeviationMeter::Feet f = dev_->piece(piece, reach(mn));
  // the step counts in the segment of its middle's foot point; where the deviation did not need the middle, in
  // the segment of its ends' foot points when they share one
  // (f.a is the previous step's f.b: its segment is remembered)
  const int seg_a = f.a == foot_ ? foot_seg_ : segment_of(f.a), seg_b = segment_of(f.b);
  foot_ = f.b;
  foot_seg_ = seg_b;
  int seg;
  if (!std::isnan(f.m))
    seg = segment_of(f.m);
  else if (seg_a == seg_b)
    seg = seg_a;
  else
    seg = segment_of(dev_->middle_foot(piece, reach(mn)));
  (axis == kAxisRadial ? nr_ : nt_)[static_cast<size_t>(seg)] += 1;
  (axis == kAxisRadial ? n : m) += dir;
}

void ErrorMeters::stream_from(int64_t n0, int64_t m0) {
  if (!path_) throw std::logic_error("ErrorMeters::stream_from before reset");
  start_following(n0, m0);
  area_.stream_from(n0, m0);
  // the area meter, the larger part, on a thread of its own; the deviation with the caller, who reads the steps
  if (parallel_) lane_ = std::make_unique<StepLane>([this](const uint8_t* s, size_t n) { area_all(s, n); });
}

ErrorMetrics ErrorMeters::finish(int64_t n0, int64_t m0) {
  ErrorMetrics out;
  if (lane_) {
    lane_->close();
    lane_.reset();
    out.area = area_.finish(n0, m0);  // checks that the staircase follows the path
  } else if (dev_) {
    out.area = area_.finish(n0, m0);
  } else if (parallel_) {
    // recorded: the area meter computes on a second thread while the deviation replays the steps
    std::exception_ptr area_err, dev_err;
    std::thread th([&] {
      try {
        out.area = area_.finish(n0, m0);
      } catch (...) {
        area_err = std::current_exception();
      }
    });
    try {
      start_following(n0, m0);
      follow_all(steps_.data(), steps_.size());
    } catch (...) {
      dev_err = std::current_exception();
    }
    th.join();
    if (area_err) std::rethrow_exception(area_err);  // the staircase does not follow the path: that first
    if (dev_err) std::rethrow_exception(dev_err);
  } else {
    out.area = area_.finish(n0, m0);
    start_following(n0, m0);
    follow_all(steps_.data(), steps_.size());
  }
  const double dr = grid_.dr, dth = grid_.dtheta;
  out.deviation_max_m = dev_->max();
  out.deviation_at = dev_->at();

  const double rmax = track_->r_max().value, K = dr / dth;
  out.deviation_eq41_m = rmax <= K ? dr : rmax * dth;
  out.segments = segments_;
  const std::vector<Vec2> pts = segment_points(*path_, segments_);
  out.f_counts = f1_counts(pts, nr_, nt_, dr, dth);
  out.f_chords = f1_chords(pts, dr, dth);
  steps_.clear();
  dev_.reset();
  return out;
}

}  // namespace polarcam
