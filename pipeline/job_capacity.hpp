#pragma once
// Job -> capacity glue (`polarcam capacity`, the report; docs/optimum-loading.md): the largest speed and load of a
// job at its placement, and the capacity curve (the largest load against speed) that replaces the composite graphs
// of Ch. 7. Numbers only; cmd_capacity and the report format them.
#include <optional>
#include <vector>

#include "job/job.hpp"
#include "pipeline/job_analysis.hpp"
#include "optimize/capacity.hpp"

namespace polarcam {

struct CapacityPoint {
  double speed = 0.0;            // m/s (the cruise or top speed)
  std::optional<double> load;    // the largest load there (kg, m, or a factor on the job's force)
  bool capped = false;
};

struct JobCapacity {
  std::optional<double> speed;   // the job's cruise speed (none for a speed table)
  double top_speed = 0.0;        // its cruise speed, or the table's largest
  double limit = 1.0;            // 1 / safety factor
  LoadMeasure measure = LoadMeasure::none;
  double load_at_job = 0.0;      // the measure's value in the job
  SpeedCapacity speed_cap;       // factors on the job's speeds
  LoadCapacity load_cap;         // at the job's speed (or `at_speed`)
  double load_speed = 0.0;       // m/s at which load_cap was found
  std::vector<CapacityPoint> curve;
};

// `at_speed`: find the largest load at this speed instead of the job's (a constant-speed job). `curve_points`: that
// many speeds, evenly from 15 % of the speed at which a motor reaches its top step rate to it (without a step-rate
// limit: of twice the usable speed, at least twice the job's); 0: no curve. Throws InputError naming the job file.
// A time-optimal job (docs/time-optimal.md, "Capacity"): refused without `at_speed`; with it, the capacity of the job
// run at that constant speed.
JobCapacity job_capacity(const Job& job, const PreparedDynamics& prep, std::optional<double> at_speed, int curve_points);

// The largest usable speed factor: the torque-limited one, or the step-rate one when lower (nullopt: none).
std::optional<double> usable_speed_factor(const JobCapacity& c);

// A load measure's value in display units: kg, mm, or N (the force's magnitude); and its name and unit.
double load_display(const Job& job, LoadMeasure m, double value);
const char* load_display_unit(LoadMeasure m);
const char* load_display_name(LoadMeasure m);

// The largest mass on the carriage as a multiple of the carriage's own mass (M_c), when it is more than
// kTheoreticalLoadFactor times it: such a load is a limit of the motors' torque only (the arm, the screw, the nut
// and the bearings are not modelled and would not carry it). nullopt for other measures, no limit, or a smaller one.
inline constexpr double kTheoreticalLoadFactor = 10.0;
std::optional<double> theoretical_load_factor(const Job& job, const JobCapacity& c);

}  // namespace polarcam
