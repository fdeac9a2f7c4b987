#pragma once
// The load-carrying capacity of a placed job (Sec. 6.6.2-6.6.3 of A. Fahim's thesis (1983), "scaling";
// docs/optimum-loading.md): the largest speed, and the largest load (added mass, depth of cut, or tool force), at
// which the worst torque ratio along the path reaches the limit 1 / safety factor. The thesis scaled the ratios of its
// optimum by Eq. 6.1-6.12 (linear in the load, quartic in the speed); here the same machine model as `analyze` is
// evaluated at every trial value and the crossing is found by bracketing and bisection, so the answer fed back into
// `analyze` gives the limit exactly (to the bisection's 1e-10, far below the analysis's refinement).
#include <optional>
#include <vector>

#include "machine/dynamics/dynamics_case.hpp"

namespace polarcam {

struct CapacityOptions {
  double rel_tol = 1e-10;     // bisection, relative in the factor or load
  double max_speed_factor = 100.0;
  double min_speed_factor = 1e-3;
  AnalysisOptions analysis;   // as `analyze` samples: searched at search_analysis(), the answer confirmed at this
                              // sampling (and searched again at it if not); keep_series is ignored
};

struct SpeedCapacity {
  // The largest factor on the job's speeds up to which the worst torque ratio stays within the limit, reached
  // from the job's speed: the first crossing above it when the job passes, the first passing factor below it when
  // it does not. nullopt: nothing down to min_speed_factor passes.
  std::optional<double> factor;
  bool capped = false;        // still within the limit at max_speed_factor
  double worst = 0.0;         // worst torque ratio at `factor`
  // The factor at which the first motor reaches its maximum step rate (nullopt: no motor has a limit).
  std::optional<double> step_rate_factor;
  int evaluations = 0;
};
SpeedCapacity speed_capacity(const PlacedPath& path, const DynamicsSetup& setup, const CapacityOptions& o = {});

enum class LoadMeasure { none, mass, depth, force };
const char* to_string(LoadMeasure m);
// What a load is scaled by: inertial -> the added mass, grinding -> the depth of cut, force -> both force
// components together; none -> nothing.
LoadMeasure load_measure(const LoadSpec& spec);

struct LoadCapacity {
  LoadMeasure measure = LoadMeasure::none;
  // The largest value of the measure (kg, m, or the factor on the job's force) at which the worst torque ratio
  // stays within the limit, reached from the job's value (upwards when the job passes there, the largest passing
  // value below it when it does not). nullopt: not even a vanishing load passes.
  std::optional<double> value;
  bool capped = false;        // still within the limit at the cap (1e6 times the job's value, or 1e7 kg of mass)
  double worst = 0.0;         // worst torque ratio there
  int evaluations = 0;
};
// At the job's speeds multiplied by `speed_factor`; `setup.load` is replaced by `spec` scaled.
LoadCapacity load_capacity(const PlacedPath& path, const DynamicsSetup& setup, const LoadSpec& spec,
                           double speed_factor = 1.0, const CapacityOptions& o = {});

// The load spec with its measure set to `value` (kg, m, or a factor on the job's force).
LoadSpec scaled_load(const LoadSpec& spec, LoadMeasure m, double value);

// The worst torque ratio at a speed factor and a load (+inf beyond a tabulated pull-out curve).
double worst_ratio_at(const PlacedPath& path, const DynamicsSetup& setup, const AnalysisOptions& a,
                      double speed_factor);

}  // namespace polarcam
