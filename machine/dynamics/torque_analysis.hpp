#pragma once
// Torques, pull-out torques and torque ratios of both axes along a whole path (Sec. 5.5 of
// A. Fahim's thesis (1983)): a series of samples, and the maxima with where they occur.
//
// Sampling. The path is cut into segments at the pieces of its polar track, at every reversal of the arm
// (theta' = 0, where the Coulomb friction of the arm support changes sign) and where the speed profile's
// acceleration jumps; every quantity is smooth inside a segment. Each segment gets at least `min_per_segment`
// intervals (fewer, down to 2, when the segments are so many that this would exceed `target_samples`: a speed
// table of thousands of stations), and more so that samples lie at most `spacing` apart along the path. Segment ends are evaluated as
// one-sided limits, so a jump appears as two samples at the same arc length.
// Maxima. The largest samples of each quantity are refined by Brent's method inside their segment, so the maxima
// do not depend on the sampling (beyond missing a peak narrower than the spacing).
// Cost: one evaluation of the path and the models per sample, plus about a thousand for the refinement; no
// digitizing. The torque-balancing optimiser calls it as its objective, with keep_series = false.
#include <vector>

#include "cam/curve.hpp"
#include "digitizer/polar_track.hpp"
#include "digitizer/speed_profile.hpp"
#include "machine/dynamics/axis_torque.hpp"

namespace polarcam {

struct AnalysisOptions {
  double spacing = 0.0;  // m between samples along the path; 0: length / target_samples
  int target_samples = 4000;
  int min_per_segment = 16;
  bool keep_series = true;  // false: maxima only
  // The maxima of the torques' magnitudes and of their sum refined too (false: those three are the sampled maxima;
  // the ratios, the step rates and the balanced objective are always refined).
  bool refine_torques = true;
};

// The sampling of the searches that analyse a path many times (the pole placement's torque objectives, the speed
// and load capacities, the constant-speed plan): maxima only, 1000 samples along the path (each segment still gets
// `min_per_segment`), since the maxima are refined between samples and so do not depend on the sampling beyond a
// peak narrower than two spacings; the torques' magnitudes not refined (no search reads them)
// (docs/optimum-loading.md, "Sampling of the searches"). What a search finds is reported from an analysis at the
// default sampling.
AnalysisOptions search_analysis();

// The kinematics of a sample (PathState without its unit vectors).
struct SampleKinematics {
  double V = 0.0, a_t = 0.0, kappa = 0.0, gamma = 0.0;
  double r_dot = 0.0, theta_dot = 0.0, r_ddot = 0.0, theta_ddot = 0.0, a_cr = 0.0, a_cn = 0.0;
  SampleKinematics() = default;
  explicit SampleKinematics(const PathState& p)
      : V(p.V),
        a_t(p.a_t),
        kappa(p.kappa),
        gamma(p.gamma),
        r_dot(p.r_dot),
        theta_dot(p.theta_dot),
        r_ddot(p.r_ddot),
        theta_ddot(p.theta_ddot),
        a_cr(p.a_cr),
        a_cn(p.a_cn) {}
};

// The balanced-torque objective of Sec. 6.6.2 at one point (docs/optimum-loading.md): with the torques normalised by
// the pull-out torques, T_T / |1 - |T_R - T_theta||, read as (|ratio_R| + |ratio_theta|) / (1 - ||ratio_R| -
// |ratio_theta||). +inf where ||ratio_R| - |ratio_theta|| >= 1 (one motor is over its pull-out torque by at least what
// the other has to spare; beyond that the printed |1 - ...| would fall again and reward overloading it further).
double balanced_torque(double ratio_R, double ratio_theta);

// One row of the series.
struct TorqueSample {
  double s = 0.0, t = 0.0;      // m of path from the start, s from the start
  double u = 0.0;               // path parameter
  double theta = 0.0, r = 0.0;  // rad (machine angle: the track's theta + theta_shift), m
  SampleKinematics st;
  ToolForce force;
  AxisDemand radial, angular;
  double total_torque() const { return std::abs(radial.torque) + std::abs(angular.torque); }
  double ratio_sum() const { return std::abs(radial.ratio) + std::abs(angular.ratio); }
  double balanced() const { return balanced_torque(radial.ratio, angular.ratio); }
};

struct Extreme {
  double value = 0.0;
  TorqueSample at;
};

struct AxisExtremes {
  Extreme ratio;      // max |torque / pull-out|
  Extreme torque;     // max |torque|
  Extreme step_rate;  // max motor step rate
};

// A corner of the path: the direction of travel jumps there, so at a non-zero speed the axis speeds jump too (an
// impulse the quasi-static model of the thesis does not cover).
struct Corner {
  double s = 0.0, theta = 0.0, r = 0.0;  // where
  double turn = 0.0;                     // rad, signed change of the direction of travel (+ left)
  double radial_rate_jump = 0.0;         // Hz, |change of the radial motor's signed step rate|
  double angular_rate_jump = 0.0;        // Hz, likewise for the angular motor
};

struct TorqueAnalysis {
  AxisExtremes radial, angular;
  Extreme total_torque;  // max |T_R| + |T_theta| (T_T, Eq. 6.29, of magnitudes)
  Extreme ratio_sum;     // max |T_R / T_pR| + |T_theta / T_ptheta| (the normalised T_T of Eq. 6.30)
  Extreme balanced;      // max of balanced_torque() along the path: the objective of Sec. 6.6.2
  std::vector<TorqueSample> series;
  std::vector<Corner> corners;
  size_t samples = 0;
  double length = 0.0, duration = 0.0;  // m, s
};

// A path ready for the dynamics.
struct DynamicsInput {
  const Curve* path = nullptr;        // tool-centre path, origin at the machine pole
  const PolarTrack* track = nullptr;  // its polar track
  double theta_shift = 0.0;           // rad added to the track's theta (place_on_grid)
  const SpeedProfile* profile = nullptr;
  const MachineModel* machine = nullptr;
  const Load* load = nullptr;
  int side = 1;  // +1 tool centre left of the travel, -1 right
};

// Throws OutsideCurveError when a step rate leaves a motor's tabulated pull-out curve (naming the axis and place).
TorqueAnalysis analyze_torques(const DynamicsInput& in, const AnalysisOptions& opt = {});

}  // namespace polarcam
