#include "machine/dynamics/time_optimal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "cam/error.hpp"
#include "cam/format.hpp"

namespace polarcam {

const char* to_string(Binding b) {
  static constexpr const char* kNames[] = {"radial torque", "angular torque", "radial step rate", "angular step rate",
                                           "angular speed", "speed",          "acceleration",     "rest"};
  return kNames[static_cast<int>(b)];
}

const char* to_string(Phase p) {
  static constexpr const char* kNames[] = {"steady", "accelerating", "braking"};
  return kNames[static_cast<int>(p)];
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The planner aims this fraction under every limit, so that what the grid between its stations does not see (the
// geometry varies between them, the passes bisect) rarely crosses the limit itself; the check then holds the limits
// exactly. It costs about kMargin / 2 of the speed.
constexpr double kMargin = 2e-4;

// The admissible tangential accelerations at one station and speed.
struct Bounds {
  bool ok = false;
  double lo = -kInf, hi = kInf;
  Binding lo_by = Binding::acceleration, hi_by = Binding::acceleration;
  Binding fail_by = Binding::radial_torque;  // when !ok: the constraint that has no room
};

class Planner {
 public:
  Planner(const PlacedPath& p, const MachineModel& m, const Load& load, const TimeOptimalLimits& lim)
      : p_(p), m_(m), load_(load), lim_(lim), limit_((1.0 - kMargin) / lim.safety_factor) {
    const PolarTrack& tr = *p.track;
    L_ = tr.length();
    const int n = std::max(8, lim.stations);
    s_.resize(static_cast<size_t>(n) + 1);
    cp_.resize(s_.size());
    cap_.assign(s_.size(), kInf);
    cap_by_.assign(s_.size(), Binding::speed);
    for (size_t i = 0; i < s_.size(); ++i) {
      s_[i] = i + 1 == s_.size() ? L_ : L_ * static_cast<double>(i) / n;
      const auto [piece, t] = tr.locate(s_[i]);
      const TrackPiece& pc = tr.pieces()[piece];
      cp_[i] = p.path->eval(pc.u_at(t), 2);
      // speed caps that depend on V alone: step rates and the arm's angular speed are proportional to V
      const PathState u = path_state(cp_[i], 1.0, 0.0);
      const double rate_R = m.mech.k_R * std::abs(u.r_dot) * m.radial.steps_per_rev;
      const double rate_T = m.mech.k_theta * std::abs(u.theta_dot) / (2.0 * std::numbers::pi) * m.angular.steps_per_rev;
      auto cap = [&](std::optional<double> lim_v, double per_unit, Binding b) {
        if (lim_v && per_unit > 0.0 && *lim_v / per_unit * (1.0 - kMargin) < cap_[i]) {
          cap_[i] = *lim_v / per_unit * (1.0 - kMargin);
          cap_by_[i] = b;
        }
      };
      cap(lim.max_speed, 1.0, Binding::speed);
      cap(m.radial.max_step_rate, rate_R, Binding::radial_step_rate);
      cap(m.angular.max_step_rate, rate_T, Binding::angular_step_rate);
      if (auto* c = std::get_if<PulloutCurve>(&m.radial.model)) cap(c->rates().back(), rate_R, Binding::radial_step_rate);
      if (auto* c = std::get_if<PulloutCurve>(&m.angular.model))
        cap(c->rates().back(), rate_T, Binding::angular_step_rate);
      cap(lim.max_angular_speed, std::abs(u.theta_dot), Binding::angular_speed);
    }
  }

  size_t size() const { return s_.size(); }
  double s(size_t i) const { return s_[i]; }
  double length() const { return L_; }

  Bounds bounds(size_t i, double V) const {
    Bounds b;
    if (lim_.max_acceleration) {
      b.lo = -*lim_.max_acceleration * (1.0 - kMargin);
      b.hi = *lim_.max_acceleration * (1.0 - kMargin);
    }
    PointDynamics d0, d1;
    try {
      d0 = point_dynamics(path_state(cp_[i], V, 0.0), s_[i], m_, load_, p_.side, FrictionMode::moving);
      d1 = point_dynamics(path_state(cp_[i], V, 1.0), s_[i], m_, load_, p_.side, FrictionMode::moving);
    } catch (const OutsideCurveError&) {
      b.fail_by = cap_by_[i];
      return b;
    }
    const AxisDemand* a0[2] = {&d0.radial, &d0.angular};
    const AxisDemand* a1[2] = {&d1.radial, &d1.angular};
    for (int k = 0; k < 2; ++k) {
      const Binding by = k == 0 ? Binding::radial_torque : Binding::angular_torque;
      const double T0 = a0[k]->torque, A = a1[k]->torque - T0, P = a0[k]->pullout * limit_;
      if (!(P > 0.0)) {
        b.fail_by = by;
        return b;
      }
      if (std::abs(A) <= 1e-12 * (std::abs(T0) + P)) {
        if (std::abs(T0) > P) {
          b.fail_by = by;
          return b;
        }
        continue;
      }
      const double x = (-P - T0) / A, y = (P - T0) / A;
      const double lo = std::min(x, y), hi = std::max(x, y);
      if (lo > hi || hi < b.lo || lo > b.hi) {
        // this axis alone, or against the other bounds: name the axis whose own interval is the tighter culprit
        b.fail_by = by;
        return b;
      }
      if (lo > b.lo) {
        b.lo = lo;
        b.lo_by = by;
      }
      if (hi < b.hi) {
        b.hi = hi;
        b.hi_by = by;
      }
    }
    b.ok = b.lo <= b.hi;
    return b;
  }

  // The velocity limit curve at station i: the largest V up to the caps with an admissible acceleration.
  double limit_speed(size_t i, Binding& by) const {
    double hi = cap_[i];
    by = cap_by_[i];
    if (std::isfinite(hi) && bounds(i, hi).ok) return hi;
    double lo = 0.0;
    if (!bounds(i, 0.0).ok)
      throw InputError(std::string("the machine cannot move along the path even at rest within the safety factor (") +
                       to_string(bounds(i, 0.0).fail_by) + " over 1/SF " + significant(s_[i] * 1e3, 6) +
                       " mm along the path): lower the load or the safety factor");
    if (!std::isfinite(hi)) {
      double v = 1e-3;
      while (v < 1e4 && bounds(i, v).ok) {
        lo = v;
        v *= 2.0;
      }
      if (v >= 1e4) return lo;  // faster than anything a machine does: held there
      hi = v;
    }
    for (int it = 0; it < 60 && hi - lo > 1e-12 * hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (bounds(i, mid).ok) {
        lo = mid;
      } else {
        hi = mid;
      }
    }
    by = bounds(i, hi).fail_by;
    return lo;
  }

  void build_limit_curve() {
    mvc_.resize(size());
    mvc_by_.resize(size());
    for (size_t i = 0; i < size(); ++i) mvc_[i] = limit_speed(i, mvc_by_[i]);
  }

  // Lowers the limit at station i to v (the check found the schedule over a limit near it).
  void lower(size_t i, double v) { mvc_[i] = std::min(mvc_[i], std::max(0.0, v)); }
  double limit_at(size_t i) const { return mvc_[i]; }

  // Forward and backward passes: V at every station.
  std::vector<double> passes() const {
    const size_t n = size();
    std::vector<double> x(n);
    for (size_t i = 0; i < n; ++i) x[i] = mvc_[i] * mvc_[i];
    x.front() = x.back() = 0.0;
    auto ok_at = [&](size_t i, double xi, double a) {
      const Bounds b = bounds(i, std::sqrt(xi));
      const double tol = 1e-9 * (std::abs(a) + 1e-9);
      return b.ok && a >= b.lo - tol && a <= b.hi + tol;
    };
    // one interval: the largest x at `to` reachable from x_from at `from` with a feasible constant acceleration,
    // no more than x_cap
    auto reach = [&](size_t from, size_t to, double xf, double x_cap, double dir) {
      const double h = std::abs(s_[to] - s_[from]);
      const Bounds b = bounds(from, std::sqrt(xf));
      if (!b.ok) return std::min(x_cap, xf);
      // dir +1: forward (accelerate by hi); -1: backward (brake by lo)
      const double a_ext = dir > 0 ? b.hi : b.lo;
      double cand = std::min(x_cap, std::max(0.0, xf + dir * 2.0 * h * a_ext));
      auto a_of = [&](double xt) { return dir * (xt - xf) / (2.0 * h); };
      if (ok_at(to, cand, a_of(cand)) && ok_at(from, xf, a_of(cand))) return cand;
      double lo = std::max(0.0, dir > 0 ? xf + 2.0 * h * std::min(0.0, b.lo) : xf - 2.0 * h * std::max(0.0, b.hi));
      lo = std::min(lo, cand);
      double hi = cand;
      for (int it = 0; it < 40; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (ok_at(to, mid, a_of(mid)) && ok_at(from, xf, a_of(mid))) {
          lo = mid;
        } else {
          hi = mid;
        }
      }
      return lo;
    };
    for (size_t i = 0; i + 1 < n; ++i) x[i + 1] = std::min(x[i + 1], reach(i, i + 1, x[i], x[i + 1], 1.0));
    for (size_t i = n - 1; i > 0; --i) x[i - 1] = std::min(x[i - 1], reach(i, i - 1, x[i], x[i - 1], -1.0));
    std::vector<double> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = std::sqrt(std::max(0.0, x[i]));
    // two neighbours at rest would never move: impossible unless the limit curve is zero there
    for (size_t i = 1; i < n; ++i)
      if (!(v[i] + v[i - 1] > 0.0))
        throw InputError("the time-optimal schedule stops " + significant(s_[i] * 1e3, 6) +
                         " mm along the path: no speed there keeps every torque ratio within 1/SF; lower the load or the "
                         "safety factor");
    return v;
  }

  // The constraint closest to its limit at station i with speed V and acceleration a: value / limit.
  std::pair<double, Binding> tightest(size_t i, double V, double a) const {
    std::pair<double, Binding> best{0.0, Binding::rest};
    auto offer = [&](double t, Binding b) {
      if (t > best.first) best = {t, b};
    };
    PointDynamics d;
    try {
      d = point_dynamics(path_state(cp_[i], V, a), s_[i], m_, load_, p_.side, FrictionMode::moving);
    } catch (const OutsideCurveError&) {
      return {kInf, cap_by_[i]};
    }
    offer(std::abs(d.radial.torque) / (d.radial.pullout * limit_), Binding::radial_torque);
    offer(std::abs(d.angular.torque) / (d.angular.pullout * limit_), Binding::angular_torque);
    if (std::isfinite(cap_[i]) && cap_[i] > 0.0) offer(V / cap_[i], cap_by_[i]);
    if (lim_.max_acceleration) offer(std::abs(a) / (*lim_.max_acceleration * (1.0 - kMargin)), Binding::acceleration);
    return best;
  }

  // Stretches of the schedule with the same binding constraint (the one closest to its limit on each interval);
  // a stretch is steady when its speed changes by less than 1 % from end to end.
  std::vector<ScheduleStretch> stretches(const std::vector<double>& v) const {
    std::vector<ScheduleStretch> out;
    std::vector<std::pair<double, double>> speeds;  // V at the ends of each stretch
    for (size_t i = 0; i + 1 < size(); ++i) {
      const double h = s_[i + 1] - s_[i];
      const double a = (v[i + 1] * v[i + 1] - v[i] * v[i]) / (2.0 * h);
      const auto t0 = tightest(i, v[i], a), t1 = tightest(i + 1, v[i + 1], a);
      const Binding b = (i + 2 == size() && v[i + 1] == 0.0 && t0.first < 0.999 && t1.first < 0.999)
                            ? Binding::rest
                            : (t0.first >= t1.first ? t0.second : t1.second);
      if (!out.empty() && out.back().binding == b) {
        out.back().s1 = s_[i + 1];
        speeds.back().second = v[i + 1];
      } else {
        out.push_back({s_[i], s_[i + 1], Phase::limit, b});
        speeds.emplace_back(v[i], v[i + 1]);
      }
    }
    for (size_t k = 0; k < out.size(); ++k) {
      const auto [va, vb] = speeds[k];
      if (vb > 1.01 * va) {
        out[k].phase = Phase::accelerate;
      } else if (va > 1.01 * vb) {
        out[k].phase = Phase::brake;
      } else {
        out[k].phase = Phase::limit;
      }
    }
    return out;
  }

 private:
  const PlacedPath& p_;
  const MachineModel& m_;
  const Load& load_;
  const TimeOptimalLimits& lim_;
  double limit_, L_ = 0.0;
  std::vector<double> s_, cap_, mvc_;
  std::vector<Binding> cap_by_, mvc_by_;
  std::vector<CurvePoint> cp_;
};

// value / limit of a sample's worst quantity (> 1: over)
double sample_excess(const TorqueSample& x, const MachineModel& m, const TimeOptimalLimits& lim) {
  const double limit = 1.0 / lim.safety_factor;
  double e = std::max(std::abs(x.radial.ratio), std::abs(x.angular.ratio)) / limit;
  if (m.radial.max_step_rate) e = std::max(e, x.radial.step_rate / *m.radial.max_step_rate);
  if (m.angular.max_step_rate) e = std::max(e, x.angular.step_rate / *m.angular.max_step_rate);
  if (lim.max_angular_speed) e = std::max(e, std::abs(x.st.theta_dot) / *lim.max_angular_speed);
  if (lim.max_speed) e = std::max(e, x.st.V / *lim.max_speed);
  if (lim.max_acceleration) e = std::max(e, std::abs(x.st.a_t) / *lim.max_acceleration);
  return std::isnan(e) ? kInf : e;
}

}  // namespace

bool schedule_within_limits(const TorqueAnalysis& a, const MachineModel& m, const TimeOptimalLimits& lim, double tol,
                            double* excess) {
  const double limit = 1.0 / lim.safety_factor;
  bool ok = a.radial.ratio.value <= limit + tol && a.angular.ratio.value <= limit + tol;
  double worst = std::max(a.radial.ratio.value, a.angular.ratio.value) / limit;
  auto rate = [&](const std::optional<double>& mx, double v) {
    if (!mx) return;
    ok = ok && v <= *mx * (1.0 + tol);
    worst = std::max(worst, v / *mx);
  };
  rate(m.radial.max_step_rate, a.radial.step_rate.value);
  rate(m.angular.max_step_rate, a.angular.step_rate.value);
  for (const TorqueSample& x : a.series) {
    const double e = sample_excess(x, m, lim);
    worst = std::max(worst, e);
    if (lim.max_angular_speed && std::abs(x.st.theta_dot) > *lim.max_angular_speed * (1.0 + tol)) ok = false;
    if (lim.max_speed && x.st.V > *lim.max_speed * (1.0 + tol)) ok = false;
    if (lim.max_acceleration && std::abs(x.st.a_t) > *lim.max_acceleration * (1.0 + tol)) ok = false;
  }
  if (excess) *excess = worst;
  return ok;
}

TimeOptimalSchedule time_optimal_speed(const PlacedPath& p, const MachineModel& m, const Load& load,
                                       const TimeOptimalLimits& lim, const AnalysisOptions& check) {
  if (!(lim.safety_factor >= 1.0) || !std::isfinite(lim.safety_factor))
    throw InputError("the safety factor must be a number of at least 1");
  Planner pl(p, m, load, lim);
  pl.build_limit_curve();
  AnalysisOptions opt = check;
  opt.keep_series = true;
  const DynamicsInput base{p.path, p.track, p.theta_shift, nullptr, &m, &load, p.side};
  constexpr double kTol = 1e-4;  // lowering goes a little beyond the excess found, so that the rounds converge
  TimeOptimalSchedule r;
  for (int round = 1;; ++round) {
    const std::vector<double> v = pl.passes();
    r.stations.resize(v.size());
    for (size_t i = 0; i < v.size(); ++i) r.stations[i] = {pl.s(i), v[i]};
    r.profile = make_table_speed_sq(r.stations, pl.length());
    DynamicsInput in = base;
    in.profile = r.profile.get();
    r.check = analyze_torques(in, opt);
    r.rounds = round;
    double excess = 0.0;
    if (schedule_within_limits(r.check, m, lim, 0.0, &excess)) break;
    if (round >= lim.max_rounds)
      throw InputError("the time-optimal schedule is still " + significant((excess - 1.0) * 100.0, 3) +
                       " % over a limit after " + std::to_string(round) +
                       " rounds of lowering it; raise the number of stations");
    // lower the limit at the stations around every sample over a limit, by the square root of its excess (the
    // torques grow with V^2 and V x'), a little more so that the rounds converge
    std::vector<const TorqueSample*> over;
    for (const TorqueSample& x : r.check.series)
      if (sample_excess(x, m, lim) > 1.0) over.push_back(&x);
    for (const Extreme* e : {&r.check.radial.ratio, &r.check.angular.ratio, &r.check.radial.step_rate,
                             &r.check.angular.step_rate})
      if (sample_excess(e->at, m, lim) > 1.0) over.push_back(&e->at);
    const double h = pl.length() / static_cast<double>(pl.size() - 1);
    for (const TorqueSample* x : over) {
      const double f = (1.0 - 20.0 * kTol) / std::sqrt(std::min(sample_excess(*x, m, lim), 1e6));
      const double pos = x->s / h;
      const auto j0 = static_cast<size_t>(std::clamp(std::floor(pos), 0.0, static_cast<double>(pl.size() - 1)));
      for (size_t j = j0 > 0 ? j0 - 1 : 0; j <= std::min(pl.size() - 1, j0 + 2); ++j)
        pl.lower(j, std::min(v[j], pl.limit_at(j)) * f);
    }
  }
  r.worst_ratio = worst_torque_ratio(r.check);
  const std::vector<double> v = [&] {
    std::vector<double> w(r.stations.size());
    for (size_t i = 0; i < w.size(); ++i) w[i] = r.stations[i].v;
    return w;
  }();
  r.stretches = pl.stretches(v);
  return r;
}

}  // namespace polarcam
