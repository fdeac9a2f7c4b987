#include "pipeline/pattern_study.hpp"

#include <cmath>

namespace polarcam {

bool pattern_report_applies(const Job& job) { return !job.machine.dynamics || job.machine.coupling != 0.0; }

PatternStudy study_pattern(const Job& job) {
  PatternStudy s;
  DigitizedJob d;
  s.preview = preview_job(job, 0.05, &d);  // the one pass of the digitizer: the tape's summary comes with it
  s.dig = d.result;
  if (d.lifted) {
    s.rapid_time_s = d.lifted->rapid_time_s;
    s.rapid_length_m = d.lifted->rapid_length_m;
  }
  s.excess = step_rate_excess(job, s.dig);
  s.speed_mps = job.motion.speed;
  // the digitizer's path length is the timing length: a turn of the arm at the centre counts as the arc at the
  // timing radius it is timed by (docs/patterns.md); the drawn length is the geometry's
  for (const Polyline& p : s.preview.path)
    for (size_t i = 1; i < p.x.size(); ++i) s.drawn_length_m += 1e-3 * std::hypot(p.x[i] - p.x[i - 1], p.y[i] - p.y[i - 1]);
  if (d.lifted) s.drawn_length_m = d.lifted->drawn_length_m;  // exact: the contours' own lengths
  s.nominal_time_s = s.speed_mps > 0.0 ? s.drawn_length_m / s.speed_mps : 0.0;
  for (const Polyline& q : s.preview.slowed)
    for (size_t i = 1; i < q.x.size(); ++i) s.slowed_length_m += 1e-3 * std::hypot(q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
  s.contours = job.contours;
  s.has_dynamics = job.machine.dynamics.has_value();
  s.coupled = job.machine.coupling != 0.0;
  return s;
}

}  // namespace polarcam
