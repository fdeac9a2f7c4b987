#pragma once
// The tool-centre path in the machine frame. From a contour about its own pole O1 it applies, in order:
//  1. the direction of travel and, for a closed contour, the start parameter;
//  2. the tool-radius offset (Eq. 2.1, 5.9 of the thesis in vector form): Q = P + d N, N the unit left normal,
//     d = +R_r on the left of the travel, -R_r on the right; Q' = P' (1 - d kappa). Where 1 - d kappa <= 0 the
//     offset cusps or folds and construction fails with the place named;
//  3. the placement: the machine pole O sits at O1 + C e^{j beta}, so the machine sees Q - C e^{j beta}.
// The result is itself a Curve whose origin is the machine pole; everything downstream (digitizer, error
// metrics, dynamics) works on it and never sees the placement.
#include <optional>

#include "cam/curve.hpp"

namespace polarcam {

struct Placement {
  double C = 0.0;     // m, distance from the contour pole O1 to the machine pole O
  double beta = 0.0;  // rad, direction of O from O1
  Vec2 pole() const;  // O - O1
};

enum class ToolSide { left, right, outside, inside };

struct ToolSpec {
  double radius = 0.0;  // m
  ToolSide side = ToolSide::left;
};

struct TravelSpec {
  bool reverse = false;
  std::optional<double> start_parameter;  // closed curves: where to start, in the curve's own parameter
};

class ToolPath final : public Curve {
 public:
  // `offset` is signed (+ left of travel) and already checked; use make_tool_path().
  ToolPath(CurvePtr contour, const Placement& placement, double offset, const TravelSpec& travel);

  // Derivatives up to order 3 without offset, up to order 2 with an offset (order 3 is then zero).
  CurvePoint eval(double u, int order) const override;
  std::vector<double> breakpoints() const override { return breaks_; }
  double rounding_scale() const override { return norm(pole_) + std::abs(d_) + contour_->rounding_scale(); }

  // Parameter of the underlying contour (before reversal and start shift) for a tool-path parameter.
  double contour_parameter(double u) const;
  const Curve& contour() const { return *contour_; }
  const Placement& placement() const { return placement_; }
  double offset() const { return d_; }  // signed: + left of travel
  // True when the tool path is the contour itself: no placement, no offset, forward from the contour's start.
  bool is_contour_itself() const { return pole_ == Vec2{} && d_ == 0.0 && !reverse_ && shift_ == 0.0; }

 private:
  CurvePtr contour_;
  Placement placement_;
  Vec2 pole_;
  double d_ = 0.0;
  bool reverse_ = false;
  double shift_ = 0.0;  // start offset within [0, length) of the parameter interval
  std::vector<double> breaks_;
};

using ToolPathPtr = std::shared_ptr<const ToolPath>;

// Side of the tool centre relative to the direction of travel, +1 left or -1 right, also for a tool of zero
// radius (process forces need to know which side the material is on). Throws InputError for 'outside'/'inside'
// on an open contour.
int tool_side_sign(const Curve& contour, const ToolSpec& tool, const TravelSpec& travel);

// Builds the tool-centre path. Throws InputError for an offset that folds, a corner that a round tool cannot
// follow, a start parameter on an open curve, and the like.
ToolPathPtr make_tool_path(CurvePtr contour, const Placement& placement, const ToolSpec& tool,
                           const TravelSpec& travel);

// Signed area enclosed by a closed curve (positive when counter-clockwise), by the shoelace formula on a fine
// sampling; used to decide which side is "outside".
double signed_area(const Curve& c);

// Minimum over the curve of 1 - d kappa (the offset's speed factor) and where it occurs; < 0 means the offset
// at signed distance d folds. Samples densely and refines each local minimum.
struct FoldCheck {
  double min_factor;
  double u;
};
FoldCheck offset_speed_factor_min(const Curve& c, double d);

}  // namespace polarcam
