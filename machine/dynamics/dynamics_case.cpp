#include "machine/dynamics/dynamics_case.hpp"

#include <algorithm>

#include "cam/error.hpp"

namespace polarcam {

SpeedProfilePtr MotionLaw::profile(double length, double f) const {
  if (!table.empty()) {
    std::vector<SpeedStation> t = table;
    for (auto& st : t) st.v *= f;
    return make_table_speed(std::move(t), length);
  }
  if (accel) return make_trapezoid_speed(speed * f, *accel, length);
  return make_constant_speed(speed * f, length);
}

double MotionLaw::top_speed() const {
  if (table.empty()) return speed;
  double v = 0.0;
  for (const auto& st : table) v = std::max(v, st.v);
  return v;
}

TorqueAnalysis analyze_motion(const PlacedPath& p, const DynamicsSetup& s, const AnalysisOptions& o,
                              double speed_factor) {
  const SpeedProfilePtr prof = s.motion.profile(p.track->length(), speed_factor);
  const DynamicsInput in{p.path, p.track, p.theta_shift, prof.get(), s.machine, &s.load, p.side};
  return analyze_torques(in, o);
}

CaseDynamics analyze_dynamics(const PlacedPath& p, const DynamicsSetup& s, const AnalysisOptions& o,
                              bool search_speed) {
  CaseDynamics r;
  const MachineModel& m = *s.machine;
  r.analysis = analyze_motion(p, s, o);
  r.verdict = judge(r.analysis, m, s.safety_factor);
  if (search_speed) {
    // The search samples at the searches' density (search_analysis: its maxima are refined, so they barely depend
    // on it) and confirms its answer at the caller's density; only if that fails does it search again at that
    // density.
    auto passes = [&](const AnalysisOptions& oo) {
      return [&, oo](double f) {
        if (f == 1.0) return r.verdict.go;
        try {
          return judge(analyze_motion(p, s, oo, f), m, s.safety_factor).go;
        } catch (const OutsideCurveError&) {
          return false;  // beyond the tabulated curve: not known to pass
        }
      };
    };
    const AnalysisOptions quick = search_analysis();
    AnalysisOptions full = o;
    full.keep_series = false;
    r.search = max_passing_speed_factor(passes(quick), passes(full));
  }
  return r;
}

double worst_torque_ratio(const TorqueAnalysis& a) { return std::max(a.radial.ratio.value, a.angular.ratio.value); }

}  // namespace polarcam
