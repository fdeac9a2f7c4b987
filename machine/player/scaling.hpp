#pragma once
// Speed and size scaling of a step tape, and the floating angular reference (Sec. 3.6, 3.7 and 3.11 of
// A. Fahim's thesis (1983); docs/player.md).
//  - speed scale K = num/den: every interval is divided by K (times t -> t den / num), exactly;
//  - size scale P/Q: the machine's radial index is N(n) = round(n P / Q), halves rounded up, i.e.
//    N(n) = floor((2 n P + Q) / (2 Q)), a function of the tape's absolute radial index n (the radial reference is
//    the pole, fixed); the contour scales by P/Q about the machine pole;
//  - angle offset M: the machine's angular index is m + M (the angular reference floats).
#include <cstdint>
#include <string>

#include "digitizer/digitize.hpp"  // StepSink

namespace polarcam {

// An exact positive rational, both parts > 0.
struct Ratio {
  int64_t num = 1, den = 1;
  double value() const { return static_cast<double>(num) / static_cast<double>(den); }
  bool is_one() const { return num == den; }
};

// "2", "0.25", "1.5", "3/2", "1/2": an exact positive ratio, reduced. `what` names the option in errors.
// Throws InputError for anything else (zero, negative, non-numeric, too many digits).
Ratio parse_ratio(const std::string& text, const std::string& what);
std::string to_string(const Ratio& r);

// Machine radial index for tape radial index n under size scale s (see above).
int64_t scaled_radial_index(int64_t n, const Ratio& s);

// A step stream with one axis's index scaled by s: the machine's index on that axis is N(n) = round(n s) (as
// scaled_radial_index, halves up, for any sign of n), so each step of that axis from n to n + dir becomes
// |N(n + dir) - N(n)| steps (none, one or several, at the same time) in the same direction. The other axis passes
// through. Scaling the radial axis of a polar tape scales the contour about the machine pole (Sec. 3.7); scaling
// one axis of a Cartesian tape stretches the contour along that axis only; scaling both of its axes scales it.
class ScaledAxisSink final : public StepSink {
 public:
  // `start_index`: the tape's index of the scaled axis at its start node.
  ScaledAxisSink(StepSink& out, int axis, Ratio s, int64_t start_index)
      : out_(out), axis_(axis), s_(s), n_(start_index), N_(scaled_radial_index(start_index, s)) {}
  void step(int axis, int dir, int64_t t_ns) override {
    if (axis != axis_) return out_.step(axis, dir, t_ns);
    n_ += dir;
    const int64_t N = scaled_radial_index(n_, s_);
    for (; N_ != N; N_ += dir) out_.step(axis, dir, t_ns);
  }

 private:
  StepSink& out_;
  int axis_;
  Ratio s_;
  int64_t n_, N_;
};

struct PlayScaling {
  Ratio speed;           // K: intervals divided by K
  Ratio size;            // P/Q: radial indices scaled about the pole
  int64_t angle_offset = 0;  // M: added to every angular index
};

}  // namespace polarcam
