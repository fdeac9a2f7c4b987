#include "digitizer/theta_rho.hpp"

#include "cam/error.hpp"
#include "digitizer/track_builder.hpp"

namespace polarcam {

ThetaRhoTrack ThetaRhoTrack::build(const Curve& path, double c) {
  if (!std::isfinite(c)) throw InputError("the arm's coupling must be a finite length per radian");
  ThetaRhoTrack tr;
  tr.c_ = c;
  build_axis_track(path, ThetaRhoMap{PolarMap{path.rounding_scale()}, c}, tr);
  return tr;
}

DigitizeResult digitize(const ThetaRhoTrack& track, const Grid& grid, StepRule rule, const SpeedProfile& profile,
                        StepSink* sink) {
  return digitize_arm(track, track.coupling(), grid, rule, profile, sink);
}

}  // namespace polarcam
