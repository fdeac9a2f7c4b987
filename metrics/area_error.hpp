#pragma once
// The exact area error (Eq. 4.2-4.3 of A. Fahim's thesis (1983), generalised; docs/area-error.md): the area
// enclosed between the tool-centre path and the quasi-static path of the machine, the polyline of radial
// segments and arcs about the machine pole through the grid nodes the tape visits. Exact up to rounding (the
// contour is the digitizer's polar track, accurate to rounding; the sector integrals are exact series).
//
// Feed it the steps of any polar tape, whatever rule made it: as a StepSink during digitize(), or from a
// TapeReader. Steps are recorded relative to the start node; finish() takes the start node and computes.
// A meter can be reset and reused; it keeps its storage (about 140 bytes per angular step).
//
// The work is done by StairAreaMeter, which measures any staircase of steps of a height axis (radial, y) and an
// abscissa axis (angular, x) against a track seen through sweep::TrackView; the Cartesian meter
// (cartesian_error.hpp) is the same machine on strips of x instead of sectors of theta.
#include <cstdint>
#include <vector>

#include "digitizer/digitize.hpp"
#include "digitizer/grid.hpp"
#include "digitizer/polar_track.hpp"
#include "metrics/sector_sweep.hpp"
#include "metrics/track_area.hpp"
#include "metrics/track_view.hpp"

namespace polarcam {

// The grid of a staircase as the sweep sees it.
struct StairGrid {
  sweep::Geometry geo = sweep::Geometry::polar;
  double width = 0.0;         // abscissa step: DeltaTheta (rad) or the BLU (m)
  double height = 0.0;        // height step: DeltaR or the BLU (m)
  int64_t steps_per_rev = 0;  // polar: angular steps per revolution (0: not a whole number)
};

struct StairAreaResult {
  double area_m2 = 0.0;
  uint64_t rise_steps = 0, run_steps = 0;  // steps of the height axis, of the abscissa axis
  uint64_t sectors = 0;          // sectors or strips (one abscissa step wide) holding part of the cycle
  uint64_t general_sectors = 0;  // of which were computed by the general sweep (ends, reversals, crossings)
  double shift = 0.0;            // polar: rad added to the track's angle to put it on the tape's angular branch
};

// The exact area between a track and a staircase whose nodes are (height index, abscissa index). Steps are
// recorded relative to the start node; finish() takes the start node and computes.
class StairAreaMeter {
 public:
  // Binds the meter to a track view (whose track must outlive finish()) and the staircase's grid; forgets
  // recorded steps.
  void reset(sweep::TrackView track, const StairGrid& grid);

  void rise(int dir) {  // a step of the height axis
    n_ += dir;
    ++nr_;
  }
  void run(int dir) {  // a step of the abscissa axis: the staircase's level strand over one sector or strip
    arcs_.push_back({n_, m_, -1, static_cast<int8_t>(dir)});
    m_ += dir;
  }

  // The staircase starts on node (h0, g0) (height index, abscissa index). Throws InputError when it does not
  // follow the path (its start or end is more than two grid cells from the path's, or it leaves the path's
  // abscissa range).
  StairAreaResult finish(int64_t h0, int64_t g0);

  // Testing: compute every sector with the general sweep.
  void set_force_general(bool on) { force_general_ = on; }

 private:
  struct ArcRec {
    int64_t n, m;  // node before the step, relative to the start; later absolute n and sector j
    int32_t next;
    int8_t dir;
  };
  struct Sub {
    uint32_t piece;
    double t0, t1, l0, l1, h0, h1, A0, A1;  // in travel order
  };
  struct Visit {
    int64_t j;
    uint32_t first, count;
    int32_t next;
    int8_t sigma;  // +1 / -1 monotone in that direction, 0 reverses inside the sector
    bool full;     // monotone and from one side of the sector to the other
    double hmin, hmax;
  };

  uint32_t key(int64_t j) const;
  void walk_contour(const sweep::Frame& fr);
  void add_sub(const Sub& s, int64_t j);
  void close_visit();
  void add_connector(Vec2 a, double ga, Vec2 b, double gb);
  double fast_visit(const Visit& v, double rho) const;
  Vec2 node_point(int64_t h, int64_t g) const;
  Vec2 path_point(double h, double g) const;

  sweep::TrackView track_;
  bool bound_ = false;
  StairGrid grid_;
  std::vector<LongCheb> areas_;
  std::vector<ArcRec> arcs_;
  int64_t n_ = 0, m_ = 0;
  uint64_t nr_ = 0;
  bool force_general_ = false;

  // per finish()
  int64_t j_lo_ = 0, j_hi_ = 0, nkeys_ = 0, key_lo_ = 0;
  double shift_ = 0.0;
  bool wrap_ = false;
  std::vector<int32_t> arc_head_, visit_head_;
  std::vector<uint8_t> forced_;
  std::vector<Visit> visits_;
  std::vector<Sub> subs_;
  std::vector<sweep::Strand> extra_;  // connector segments
  std::vector<int32_t> extra_head_, extra_next_;
  int open_ = -1;  // index of the visit being built
};

// A StairAreaMeter fed by a tape: steps of the tape axis `rise_axis` are the staircase's rises (its height
// axis), those of the other axis its runs. The polar and Cartesian meters are this with their track and grid.
class StairStepMeter : public StepSink {
 public:
  void step(int axis, int dir, int64_t) override { record(axis, dir); }
  void record(int axis, int dir) {
    if (axis == rise_axis_)
      core_.rise(dir);
    else
      core_.run(dir);
  }
  // Testing: compute every sector or strip with the general sweep.
  void set_force_general(bool on) { core_.set_force_general(on); }

 protected:
  explicit StairStepMeter(int rise_axis) : rise_axis_(rise_axis) {}
  StairAreaMeter core_;

 private:
  int rise_axis_;
};

// The polar meter: rises are radial steps, runs angular steps, sectors of one DeltaTheta; shift is the rad added
// to the track's angle to put it on the tape's angular branch.
using AreaErrorResult = StairAreaResult;

class PolarAreaMeter final : public StairStepMeter {
 public:
  PolarAreaMeter() : StairStepMeter(kAxisRadial) {}
  // Binds the meter to the path's track (which must outlive finish()) and the grid of the staircase (dr, dtheta,
  // steps_per_rev); forgets recorded steps.
  void reset(const PolarTrack& track, const Grid& grid);
  // The staircase starts on node (n0, m0). Throws InputError when the staircase does not follow the path (its
  // start or end is more than two grid cells from the path's, or it leaves the path's angular range).
  AreaErrorResult finish(int64_t n0, int64_t m0);

 private:
  Grid grid_;
};

}  // namespace polarcam
