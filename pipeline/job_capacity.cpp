#include "pipeline/job_capacity.hpp"

#include <algorithm>
#include <cmath>

#include "cam/error.hpp"

namespace polarcam {

namespace {

double measure_value(const LoadSpec& s, LoadMeasure m) {
  switch (m) {
    case LoadMeasure::mass: return s.mass;
    case LoadMeasure::depth: return s.grinding.depth;
    case LoadMeasure::force: return 1.0;
    default: return 0.0;
  }
}

}  // namespace

std::optional<double> usable_speed_factor(const JobCapacity& c) {
  if (!c.speed_cap.factor) return std::nullopt;
  double f = *c.speed_cap.factor;
  if (c.speed_cap.step_rate_factor) f = std::min(f, *c.speed_cap.step_rate_factor);
  return f;
}

JobCapacity job_capacity(const Job& job, const PreparedDynamics& prep, std::optional<double> at_speed,
                         int curve_points) {
  if (job.motion.time_optimal) {
    // the schedule runs every stretch as fast as its limits allow: the capacity asked is that of a constant speed
    if (!at_speed)
      throw InputError("a time-optimal schedule has no speed margin (it runs every stretch at its limits) and is "
                       "planned for the job's load: give --speed for the capacity at a constant speed, or run "
                       "`polarcam optimize-speed` for the schedule and what binds it",
                       job.file);
    Job constant = job;
    constant.motion.time_optimal = false;
    if (!(*at_speed > 0.0)) throw InputError("--speed must be positive", job.file);
    constant.motion.speed = *at_speed;
    return job_capacity(constant, prep, std::nullopt, curve_points);
  }
  JobCapacity c;
  try {
    const DynamicsSetup setup = dynamics_setup(job, DynamicsCase{std::nullopt, job.load});
    const PlacedPath path = placed_path(prep);
    if (setup.motion.table.empty()) c.speed = setup.motion.speed;
    c.top_speed = setup.motion.top_speed();
    c.limit = 1.0 / setup.safety_factor;
    c.measure = load_measure(job.load);
    c.load_at_job = measure_value(job.load, c.measure);
    c.speed_cap = speed_capacity(path, setup, {});
    double f_load = 1.0;
    if (at_speed) {
      if (!c.speed) throw InputError("--speed needs a job with a constant speed, not a speed_profile");
      if (!(*at_speed > 0.0)) throw InputError("--speed must be positive");
      f_load = *at_speed / *c.speed;
    }
    c.load_speed = c.top_speed * f_load;
    c.load_cap = load_capacity(path, setup, job.load, f_load, {});
    const std::optional<double> fu = usable_speed_factor(c);
    if (curve_points > 0 && c.measure != LoadMeasure::none) {
      // up to the highest speed the motors can step at (smaller loads pass there), or twice the usable speed
      double f_top = c.speed_cap.step_rate_factor.value_or(std::max(2.0, 2.0 * fu.value_or(1.0)));
      if (!(f_top > 0.0)) f_top = 1.0;
      CapacityOptions co;
      co.rel_tol = 1e-6;  // plenty for a curve
      for (int i = 0; i < curve_points; ++i) {
        const double f = f_top * (0.15 + 0.85 * i / std::max(1, curve_points - 1));
        const LoadCapacity lc = load_capacity(path, setup, job.load, f, co);
        c.curve.push_back({c.top_speed * f, lc.value, lc.capped});
      }
    }
  } catch (const InputError& e) {
    throw e.in_file(job.file);
  }
  return c;
}

double load_display(const Job& job, LoadMeasure m, double v) {
  switch (m) {
    case LoadMeasure::mass: return v;
    case LoadMeasure::depth: return v * 1e3;
    case LoadMeasure::force: return v * std::hypot(job.load.force.tangential, job.load.force.normal);
    default: return 0.0;
  }
}

std::optional<double> theoretical_load_factor(const Job& job, const JobCapacity& c) {
  if (c.measure != LoadMeasure::mass || !c.load_cap.value || !job.machine.dynamics) return std::nullopt;
  const double mc = job.machine.dynamics->mech.carriage_mass;
  if (!(mc > 0.0)) return std::nullopt;
  const double f = *c.load_cap.value / mc;
  if (!(f > kTheoreticalLoadFactor)) return std::nullopt;
  return f;
}

const char* load_display_unit(LoadMeasure m) {
  switch (m) {
    case LoadMeasure::mass: return "kg";
    case LoadMeasure::depth: return "mm";
    case LoadMeasure::force: return "N";
    default: return "";
  }
}

const char* load_display_name(LoadMeasure m) {
  switch (m) {
    case LoadMeasure::mass: return "mass on the carriage";
    case LoadMeasure::depth: return "depth of cut";
    case LoadMeasure::force: return "tool force";
    default: return "load";
  }
}

}  // namespace polarcam
