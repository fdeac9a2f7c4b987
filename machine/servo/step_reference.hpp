#pragma once
// The reference positions of a servo machine from a stream of axis steps at exact times (a step tape, or the
// digitizer's steps as they come): at each sample t_k = k T, the node reached by every step at or before t_k,
// times the axis resolution (docs/feed-drives.md). Axis 0 is r (polar tapes) or x (Cartesian tapes), axis 1 theta
// or y.
#include <cstdint>
#include <string>
#include <vector>

#include "digitizer/digitize.hpp"
#include "machine/servo/contour.hpp"

namespace polarcam::servo {

// Collects steps (a StepSink) and samples them.
class StepSampler final : public StepSink {
 public:
  // res: the axis resolutions (m, or rad for theta); start: the node before the first step.
  StepSampler(const double res[2], int64_t start_n, int64_t start_m);
  void begin(int64_t n, int64_t m) override;
  void step(int axis, int dir, int64_t t_ns) override;
  // The reference sampled at T from t = 0 to the last step, then held for `hold` s.
  Reference sample(double T, double hold = 0.2) const;

 private:
  struct Step {
    int64_t t_ns;
    int axis, dir;
  };
  double res_[2];
  int64_t start_[2];
  std::vector<Step> steps_;
};

// The reference of a step tape (version 1 or 2; tool events do not move the axes). `polar_drives` must match the
// tape's axes (polar or Cartesian): an InputError naming the tape otherwise.
Reference reference_from_tape(const std::string& path, bool polar_drives, double T, double hold = 0.2);

}  // namespace polarcam::servo
