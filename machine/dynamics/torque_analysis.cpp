#include "machine/dynamics/torque_analysis.hpp"

#include <algorithm>
#include <array>
#include <boost/math/tools/minima.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "cam/error.hpp"
#include "cam/format.hpp"

namespace polarcam {
namespace {

enum Quantity { kRatioR, kRatioT, kTorqueR, kTorqueT, kRateR, kRateT, kTotal, kRatioSum, kBalanced, kQuantities };
constexpr int kCandidates = 3;  // refined local maxima per quantity

double quantity(const TorqueSample& x, int q) {
  switch (q) {
    case kRatioR:
      return std::abs(x.radial.ratio);
    case kRatioT:
      return std::abs(x.angular.ratio);
    case kTorqueR:
      return std::abs(x.radial.torque);
    case kTorqueT:
      return std::abs(x.angular.torque);
    case kRateR:
      return x.radial.step_rate;
    case kRateT:
      return x.angular.step_rate;
    case kTotal:
      return x.total_torque();
    case kRatioSum:
      return x.ratio_sum();
    default:
      return x.balanced();
  }
}

// Whether a sample is the end of a segment, evaluated as the limit from below (path geometry, acceleration of the
// speed profile, friction before a reversal), so that a jump at the boundary shows on both sides; every other
// sample, the segment's start included, is the limit from above.
enum class End { none, finish };

class Evaluator {
 public:
  explicit Evaluator(const DynamicsInput& in) : in_(in) {}

  // `place`: also the machine angle, the time and the direction of travel gamma (for the series, the corners and
  // the reported places; a search's samples inside a segment do without)
  TorqueSample at(size_t piece, double t, End end, bool place = true) const {
    const TrackPiece& p = in_.track->pieces()[piece];
    TorqueSample x;
    x.u = t >= 1.0 ? p.ub : (t <= -1.0 ? p.ua : p.u_at(t));
    double u_eval = x.u;
    if (end == End::finish && t >= 1.0) u_eval = std::nextafter(p.ub, p.ua);  // left limit at a path breakpoint
    x.s = std::clamp(in_.track->s(piece, t), 0.0, in_.track->length());
    const SpeedProfile& prof = *in_.profile;
    if (place) {
      x.theta = in_.track->theta(piece, t) + in_.theta_shift;
      x.t = prof.time_at(x.s);
    }
    const double V = prof.speed_at(x.s);
    const double a_t = prof.accel_at(end == End::finish ? std::nextafter(x.s, -1.0) : x.s);
    const PathState st = path_state(in_.path->eval(u_eval, 2), V, a_t, place);
    x.r = st.r;
    const FrictionMode mode = end == End::finish ? FrictionMode::reversal_before : FrictionMode::moving;
    PointDynamics d;
    try {
      d = point_dynamics(st, x.s, *in_.machine, *in_.load, in_.side, mode);
    } catch (const OutsideCurveError& e) {
      if (!place) x.theta = in_.track->theta(piece, t) + in_.theta_shift;
      throw OutsideCurveError(std::string(e.what()) + " at theta = " + significant(x.theta, 6) + " rad, r = " +
                              significant(x.r * 1e3, 6) + " mm, " + significant(x.s * 1e3, 6) + " mm along the path");
    }
    x.st = SampleKinematics(d.st);
    x.force = d.force;
    x.radial = d.radial;
    x.angular = d.angular;
    return x;
  }

 private:
  const DynamicsInput& in_;
};

struct Candidate {
  double value = -std::numeric_limits<double>::infinity();
  size_t piece = 0;
  double t = 0;           // where the sample is
  End end = End::none;    // and which limit it is
  bool placed = true;     // false: `sample` was taken without its place (Evaluator::at)
  double lo = 0, hi = 0;  // bracket in t
  TorqueSample sample;
};

void offer(std::array<Candidate, kCandidates>& c, const Candidate& x) {
  if (!(x.value > c.back().value)) return;
  c.back() = x;
  for (size_t i = c.size() - 1; i > 0 && c[i].value > c[i - 1].value; --i) std::swap(c[i], c[i - 1]);
}

bool same_values(const TorqueSample& a, const TorqueSample& b) {
  for (int q = 0; q < kQuantities; ++q) {
    double x = quantity(a, q), y = quantity(b, q);
    if (x == y) continue;
    if (!(std::abs(x - y) <= 1e-9 * std::max({std::abs(x), std::abs(y), 1e-300}))) return false;
  }
  return true;
}

}  // namespace

AnalysisOptions search_analysis() {
  AnalysisOptions o;
  o.target_samples = 1000;
  o.keep_series = false;
  o.refine_torques = false;
  return o;
}

double balanced_torque(double ratio_R, double ratio_theta) {
  const double a = std::abs(ratio_R), b = std::abs(ratio_theta);
  const double den = 1.0 - std::abs(a - b);
  if (!(den > 0.0)) return std::numeric_limits<double>::infinity();
  return (a + b) / den;
}

TorqueAnalysis analyze_torques(const DynamicsInput& in, const AnalysisOptions& opt) {
  const PolarTrack& tr = *in.track;
  const auto& pieces = tr.pieces();
  TorqueAnalysis res;
  res.length = tr.length();
  res.duration = in.profile->total_time();
  const double h = opt.spacing > 0.0 ? opt.spacing : tr.length() / std::max(1, opt.target_samples);
  // at least min_per_segment samples a segment, but no more in all than about the target when the segments are
  // many (a speed table of thousands of stations, as a constant-force schedule is: each station is a kink), and
  // never fewer than 2 (the maxima inside a segment are refined by Brent's method between samples)
  const std::vector<double> profile_kinks = in.profile->kinks();
  const size_t segments = pieces.size() + profile_kinks.size();
  const int min_n = std::clamp(opt.target_samples / static_cast<int>(std::max<size_t>(1, segments)), 2,
                               std::max(2, opt.min_per_segment));
  constexpr double kMaxSamples = 5e7;
  if (!(h > 0.0) || tr.length() / h > kMaxSamples)
    throw InputError("a sample spacing of " + significant(h * 1e3, 6) + " mm would need " +
                     significant(tr.length() / h, 6) + " samples along the " + significant(tr.length() * 1e3, 6) +
                     " mm path, more than " + significant(kMaxSamples, 6));
  Evaluator ev(in);

  // speed-profile kinks, as (piece, t)
  std::vector<std::pair<size_t, double>> kinks;
  for (double s : profile_kinks)
    if (s > 0.0 && s < tr.length()) kinks.push_back(tr.locate(s));

  if (opt.keep_series)
    res.series.reserve(static_cast<size_t>(std::min(1e8, tr.length() / h)) +
                       pieces.size() * (static_cast<size_t>(min_n) + 1));
  auto corner = [&](const TorqueSample& before, const TorqueSample& after) {
    const double turn = std::remainder(after.st.gamma - before.st.gamma, 2.0 * std::numbers::pi);
    if (!(after.st.V > 0.0) || !(std::abs(turn) > 1e-6)) return;
    const Mechanics& mk = in.machine->mech;
    Corner c;
    c.s = after.s;
    c.theta = after.theta;
    c.r = after.r;
    c.turn = turn;
    c.radial_rate_jump = mk.k_R * std::abs(after.st.r_dot - before.st.r_dot) * in.machine->radial.steps_per_rev;
    c.angular_rate_jump = mk.k_theta * std::abs(after.st.theta_dot - before.st.theta_dot) / (2.0 * std::numbers::pi) *
                          in.machine->angular.steps_per_rev;
    res.corners.push_back(c);
  };
  std::array<std::array<Candidate, kCandidates>, kQuantities> cand;
  std::vector<TorqueSample> seg;
  std::vector<double> ts, cuts, qv;
  bool have_prev = false;
  TorqueSample prev, first;
  std::sort(kinks.begin(), kinks.end());
  size_t next_kink = 0;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const TrackPiece& p = pieces[i];
    cuts.assign({-1.0, 1.0});
    cuts.insert(cuts.end(), tr.turns().begin() + p.turn_begin, tr.turns().begin() + p.turn_end);  // the arm reverses
    while (next_kink < kinks.size() && kinks[next_kink].first < i) ++next_kink;
    for (; next_kink < kinks.size() && kinks[next_kink].first == i; ++next_kink) cuts.push_back(kinks[next_kink].second);
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end(), [](double a, double b) { return b - a <= 1e-14; }), cuts.end());
    if (cuts.back() < 1.0) cuts.back() = 1.0;
    for (size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double ta = cuts[k], tb = cuts[k + 1];
      const double len = p.S(tb) - p.S(ta);
      const int n = std::max(min_n, static_cast<int>(std::min(1e9, std::ceil(len / h))));
      auto placed = [&](int j) { return opt.keep_series || j == 0 || j == n; };
      ts.resize(static_cast<size_t>(n) + 1);
      seg.resize(ts.size());
      for (int j = 0; j <= n; ++j) {
        ts[static_cast<size_t>(j)] = j == n ? tb : ta + (tb - ta) * j / n;
        seg[static_cast<size_t>(j)] = ev.at(i, ts[static_cast<size_t>(j)], j == n ? End::finish : End::none,
                                            placed(j));
      }
      // local maxima of each quantity (the first sample of a plateau)
      qv.resize(seg.size() * kQuantities);
      for (size_t j = 0; j < seg.size(); ++j)
        for (int q = 0; q < kQuantities; ++q) qv[j * kQuantities + static_cast<size_t>(q)] = quantity(seg[j], q);
      for (int q = 0; q < kQuantities; ++q) {
        auto& cq = cand[static_cast<size_t>(q)];
        auto at = [&](int j) { return qv[static_cast<size_t>(j) * kQuantities + static_cast<size_t>(q)]; };
        for (int j = 0; j <= n; ++j) {
          const double v = at(j);
          if (!(v > cq.back().value)) continue;
          if (j > 0 && !(v > at(j - 1))) continue;
          if (j < n && v < at(j + 1)) continue;
          Candidate c;
          c.value = v;
          c.piece = i;
          c.t = ts[static_cast<size_t>(j)];
          c.end = j == n ? End::finish : End::none;
          c.placed = placed(j);
          c.lo = ts[static_cast<size_t>(std::max(0, j - 1))];
          c.hi = ts[static_cast<size_t>(std::min(n, j + 1))];
          c.sample = seg[static_cast<size_t>(j)];
          offer(cq, c);
        }
      }
      // a corner: the direction of travel jumps between the end of the previous piece and the start of this one
      if (have_prev && k == 0) corner(prev, seg.front());
      // a segment start that continues the previous segment's end smoothly is the same point twice: counted once,
      // whether the series is kept or not
      const size_t skip = (have_prev && same_values(prev, seg.front())) ? 1 : 0;
      res.samples += seg.size() - skip;
      if (opt.keep_series) {
        res.series.insert(res.series.end(), seg.begin() + static_cast<std::ptrdiff_t>(skip), seg.end());
      }
      if (!have_prev) first = seg.front();
      prev = seg.back();
      have_prev = true;
    }
  }
  if (tr.closed() && have_prev) corner(prev, first);  // the seam of a closed path
  if (opt.keep_series) res.samples = res.series.size();

  // refine each candidate by Brent's method inside its bracket; keep the best
  std::array<Extreme, kQuantities> best;
  for (int q = 0; q < kQuantities; ++q) {
    Extreme& b = best[static_cast<size_t>(q)];
    b.value = -std::numeric_limits<double>::infinity();
    const Candidate* sampled = nullptr;  // the best value is a sample's, not a refined one
    for (const Candidate& c : cand[static_cast<size_t>(q)]) {
      if (c.value == -std::numeric_limits<double>::infinity()) continue;
      if (c.value > b.value) {
        b = {c.value, c.sample};
        sampled = &c;
      }
      if (!std::isfinite(c.value) || !(c.hi > c.lo)) continue;
      if (!opt.refine_torques && (q == kTorqueR || q == kTorqueT || q == kTotal)) continue;
      auto f = [&](double t) {
        const double v = quantity(ev.at(c.piece, t, End::none), q);
        return std::isfinite(v) ? -v : -std::numeric_limits<double>::max();
      };
      boost::uintmax_t iters = 100;
      const auto r =
          boost::math::tools::brent_find_minima(f, c.lo, c.hi, std::numeric_limits<double>::digits / 2, iters);
      if (-r.second > b.value) {
        TorqueSample x = ev.at(c.piece, r.first, End::none);
        b = {quantity(x, q), x};
        sampled = nullptr;
      }
    }
    // a sample inside a segment was taken without its place: the same sample again with it
    if (sampled && !sampled->placed) b.at = ev.at(sampled->piece, sampled->t, sampled->end);
  }
  res.radial = {best[kRatioR], best[kTorqueR], best[kRateR]};
  res.angular = {best[kRatioT], best[kTorqueT], best[kRateT]};
  res.total_torque = best[kTotal];
  res.ratio_sum = best[kRatioSum];
  res.balanced = best[kBalanced];
  return res;
}

}  // namespace polarcam
