#pragma once
// The software digitizer (Sec. 2.3 and Appendix C of A. Fahim's thesis (1983), rebuilt): every axis step of a
// polar machine, in order, with the exact time at which it is due, for the tool centre moving along the path at
// the tangential speed of a SpeedProfile.
//
// Each axis is a quantiser of the path's continuous coordinate f (r / DeltaR or theta / DeltaTheta) with
// threshold h: from node v the axis steps up when f reaches v + h and down when f falls below v - h.
//  - rule `nearest` (h = 1/2): the node is always the grid value nearest the path point, v = floor(f + 1/2);
//    radial steps fall where the path crosses the circles r = (n + 1/2) DeltaR, angular steps where it crosses
//    the rays theta = (m + 1/2) DeltaTheta. The default.
//  - rule `thesis` (h = 1): an axis is indexed by one full resolution when the path has moved a full resolution
//    from the node (App. C: index by DeltaR or DeltaTheta, solve Eq. 2.1/2.2 for the contour point). The start
//    node truncates (ALL = INT(AL/DELR)*DELR); on a closed path the start node is the one the quantiser holds
//    after a lap, so the tape closes.
// A step's time is t(s) of the profile at the arc length s where the path meets the step's level, rounded to
// the nearest nanosecond from the start (never accumulated interval by interval, so there is no drift).
// Simultaneous steps are two events with equal times; when two steps fall at the same point the radial one
// comes first.
#include <array>
#include <cstdint>

#include "digitizer/grid.hpp"
#include "digitizer/polar_track.hpp"
#include "digitizer/speed_profile.hpp"

namespace polarcam {

enum class StepRule { nearest, thesis };
const char* to_string(StepRule r);

enum : int { kAxisRadial = 0, kAxisAngular = 1 };

class StepSink {
 public:
  virtual ~StepSink() = default;
  // axis kAxisRadial or kAxisAngular, dir +1 or -1, t_ns cumulative time of the step from the start
  virtual void step(int axis, int dir, int64_t t_ns) = 0;
  // The tool lifted (down = false) or lowered (down = true) at t_ns, between the contours of a job on a machine
  // that lifts its tool (pipeline/job_tape). Sinks that only count or follow the nodes ignore it.
  virtual void tool(bool down, int64_t t_ns) {
    (void)down;
    (void)t_ns;
  }
  // The node (radial n, angular m) the tape starts on, before its first step: called once, by the walk of a
  // tape's first track (digitize, digitize_arm; not digitize_arm_from, which continues a tape). Sinks that follow
  // the nodes (a preview) take their start from it, so that one pass of the digitizer is enough.
  virtual void begin(int64_t n, int64_t m) {
    (void)n;
    (void)m;
  }
};

// Checks the track against the work area and chooses the angular branch: returns the multiple of 2 pi added to
// the track's theta so that the whole path lies in [theta_min, theta_max] (or, without an angular range, so that
// the start angle lies in [0, 2 pi)). Throws InputError naming where the path leaves the work area.
double place_on_grid(const PolarTrack& track, const Grid& grid);
// The same for an arm whose radial motor stands at q = r + c theta (track axis 0; c in m/rad, 0 on the polar
// machine) and whose angular motor at theta (axis 1): r_min and r_max bound the ball's radius r = q - c theta
// (theta_rho.hpp).
double place_on_grid_arm(const AxisTrack& track, double c, const Grid& grid);

// Checks the track against the work area on the angular branch `shift` given (InputError as place_on_grid_arm).
void check_on_grid_arm(const AxisTrack& track, double c, const Grid& grid, double shift);

struct AxisSummary {
  uint64_t plus = 0, minus = 0;
  double max_rate_hz = 0.0;              // max over the path of V |df/ds| (steps per second, geometric)
  int64_t min_interval_ns = -1;          // shortest time between consecutive steps of this axis (-1: < 2 steps)
  uint64_t steps() const { return plus + minus; }
};

struct DigitizeResult {
  int64_t start_n = 0, start_m = 0, end_n = 0, end_m = 0;
  AxisSummary radial, angular;
  double path_length_m = 0.0;
  double duration_s = 0.0;       // time to traverse the whole path
  int64_t duration_ns = 0;
  int64_t last_step_ns = 0;
  double theta_shift = 0.0;      // rad added to the track's theta (place_on_grid)
  bool closed = false;           // the path is closed
  bool returns_to_start = false; // the tape ends on its start node (same place; whole turns of the arm allowed)
  int winding = 0;               // turns about the pole of a closed path
};

// Digitizes the track. `sink` may be null (counting and timing only).
DigitizeResult digitize(const PolarTrack& track, const Grid& grid, StepRule rule, const SpeedProfile& profile,
                        StepSink* sink);
// The node (radial n, angular m) digitize() starts the tape of this track on (its start_n, start_m), found without
// walking the track (but the thesis rule's lap on a closed path). Throws InputError as digitize() does where the
// path leaves the work area.
std::array<int64_t, 2> start_node(const PolarTrack& track, const Grid& grid, StepRule rule);
// Digitizes the track of an arm with radial coupling c (m/rad) as above; digitize() of a polar track is c = 0.
DigitizeResult digitize_arm(const AxisTrack& track, double c, const Grid& grid, StepRule rule,
                            const SpeedProfile& profile, StepSink* sink);
// One piece of a job of several tracks (the contours of a multi-contour job and the rapid moves between them,
// pipeline/job_tape): the track on the angular branch `shift` given (checked against the work area), its
// quantisers continuing from `start_node` (the node the previous piece ended on, so that the steps of all pieces
// add up to the job's end node less its start node), its steps timed from t0_ns on the tape's clock. The result's
// times (duration, last step) are the piece's own, from its start.
DigitizeResult digitize_arm_from(const AxisTrack& track, double c, const Grid& grid, StepRule rule,
                                 const SpeedProfile& profile, StepSink* sink, double shift,
                                 const int64_t start_node[2], int64_t t0_ns);

}  // namespace polarcam
