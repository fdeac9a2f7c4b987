#include "optimize/capacity.hpp"

#include "machine/dynamics/largest_passing.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "cam/error.hpp"

namespace polarcam {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Analysed {
  double worst = kInf;
  double rate_over = 0.0;  // max over the axes of step rate / limit
};

Analysed analyse(const PlacedPath& path, const DynamicsSetup& setup, const AnalysisOptions& a, double f) {
  Analysed r;
  AnalysisOptions o = a;
  o.keep_series = false;
  try {
    const TorqueAnalysis t = analyze_motion(path, setup, o, f);
    r.worst = worst_torque_ratio(t);
    const MachineModel& m = *setup.machine;
    if (m.radial.max_step_rate) r.rate_over = std::max(r.rate_over, t.radial.step_rate.value / *m.radial.max_step_rate);
    if (m.angular.max_step_rate)
      r.rate_over = std::max(r.rate_over, t.angular.step_rate.value / *m.angular.max_step_rate);
  } catch (const OutsideCurveError&) {
    // beyond a tabulated pull-out curve: not known to pass
  }
  return r;
}

// The largest passing value, searched at the searches' sampling (search_analysis) and confirmed at `full`
// (confirmed_largest_passing). `pass(exact, x)`: at `full` when `exact`.
LargestPassing confirmed_passing(const std::function<bool(bool, double)>& pass, const BracketSpec& spec) {
  return confirmed_largest_passing([&](double x) { return pass(false, x); }, [&](double x) { return pass(true, x); },
                                   spec);
}

AnalysisOptions maxima_only(AnalysisOptions a) {
  a.keep_series = false;
  return a;
}

}  // namespace

double worst_ratio_at(const PlacedPath& path, const DynamicsSetup& setup, const AnalysisOptions& a, double f) {
  return analyse(path, setup, a, f).worst;
}

SpeedCapacity speed_capacity(const PlacedPath& path, const DynamicsSetup& setup, const CapacityOptions& o) {
  if (!(setup.safety_factor >= 1.0)) throw InputError("the safety factor must be a number of at least 1");
  const double limit = 1.0 / setup.safety_factor;
  const AnalysisOptions full = maxima_only(o.analysis);
  SpeedCapacity out;
  std::optional<double> last_f;  // the last passing factor at `full`, and its worst ratio
  double last_worst = kInf;
  Analysed at1;                  // at the job's speed, at `full`
  const AnalysisOptions quick = search_analysis();
  auto pass = [&](bool at_full, double f) {
    ++out.evaluations;
    const Analysed r = analyse(path, setup, at_full ? full : quick, f);
    if (at_full && f == 1.0) at1 = r;
    const bool ok = r.worst <= limit;
    if (ok && at_full) {
      last_f = f;
      last_worst = r.worst;
    }
    return ok;
  };
  const LargestPassing b = confirmed_passing(
      pass, {1.0, o.min_speed_factor, o.max_speed_factor, [](double f) { return 1.25 * f; }, o.rel_tol, true, true});
  out.factor = b.x;
  out.capped = b.capped;
  if (b.x) out.worst = (last_f && *last_f == *b.x) ? last_worst : analyse(path, setup, full, *b.x).worst;
  // the step-rate limit: exactly proportional to the speeds without a ramp; a ramp may not reach its cruise speed
  const MachineModel& m = *setup.machine;
  if (m.radial.max_step_rate || m.angular.max_step_rate) {
    if (!(at1.rate_over > 0.0)) at1 = analyse(path, setup, full, 1.0);
    if (!setup.motion.accel || !setup.motion.table.empty()) {
      if (at1.rate_over > 0.0) out.step_rate_factor = 1.0 / at1.rate_over;
    } else {
      auto rate_ok = [&](bool at_full, double f) {
        ++out.evaluations;
        return analyse(path, setup, at_full ? full : quick, f).rate_over <= 1.0;
      };
      const LargestPassing r = confirmed_passing(
          rate_ok, {1.0, o.min_speed_factor, o.max_speed_factor, [](double f) { return 1.25 * f; }, o.rel_tol, true, true});
      out.step_rate_factor = r.x;
    }
  }
  return out;
}

const char* to_string(LoadMeasure m) {
  switch (m) {
    case LoadMeasure::none: return "none";
    case LoadMeasure::mass: return "mass";
    case LoadMeasure::depth: return "depth";
    case LoadMeasure::force: return "force";
  }
  return "?";
}

LoadMeasure load_measure(const LoadSpec& spec) {
  switch (spec.kind) {
    case LoadKind::inertial: return LoadMeasure::mass;
    case LoadKind::grinding: return LoadMeasure::depth;
    case LoadKind::force: return LoadMeasure::force;
    default: return LoadMeasure::none;
  }
}

LoadSpec scaled_load(const LoadSpec& spec, LoadMeasure m, double v) {
  LoadSpec s = spec;
  switch (m) {
    case LoadMeasure::mass: s.mass = v; break;
    case LoadMeasure::depth: s.grinding.depth = v; break;
    case LoadMeasure::force:
      s.force.tangential = spec.force.tangential * v;
      s.force.normal = spec.force.normal * v;
      break;
    default: break;
  }
  return s;
}

LoadCapacity load_capacity(const PlacedPath& path, const DynamicsSetup& setup, const LoadSpec& spec,
                           double speed_factor, const CapacityOptions& o) {
  if (!(setup.safety_factor >= 1.0)) throw InputError("the safety factor must be a number of at least 1");
  LoadCapacity out;
  out.measure = load_measure(spec);
  if (out.measure == LoadMeasure::none) return out;
  const double limit = 1.0 / setup.safety_factor;
  double x0 = 1.0, x_min = 0.0, cap = 1e6;
  std::function<double(double)> grow = [](double x) { return 2.0 * x; };
  switch (out.measure) {
    case LoadMeasure::mass:
      x0 = spec.mass;
      cap = 1e7;  // kg
      grow = [](double x) { return 2.0 * x + 1.0; };
      break;
    case LoadMeasure::depth:
      x0 = spec.grinding.depth;
      x_min = 1e-9 * x0;
      cap = 1e6 * x0;
      break;
    default:
      break;
  }
  DynamicsSetup s = setup;
  const AnalysisOptions full = maxima_only(o.analysis);
  std::optional<double> last_x;  // the last passing value at `full`, and its worst ratio
  double last_worst = kInf;
  const AnalysisOptions quick = search_analysis();
  auto pass = [&](bool at_full, double x) {
    ++out.evaluations;
    s.load = make_load(scaled_load(spec, out.measure, x));
    const double w = analyse(path, s, at_full ? full : quick, speed_factor).worst;
    const bool ok = w <= limit;
    if (ok && at_full) {
      last_x = x;
      last_worst = w;
    }
    return ok;
  };
  const LargestPassing b = confirmed_passing(pass, {x0, x_min, cap, grow, o.rel_tol, true, false});
  out.value = b.x;
  out.capped = b.capped;
  if (b.x) {
    if (last_x && *last_x == *b.x) {
      out.worst = last_worst;
    } else {
      s.load = make_load(scaled_load(spec, out.measure, *b.x));
      out.worst = analyse(path, s, full, speed_factor).worst;
    }
  }
  return out;
}

}  // namespace polarcam
