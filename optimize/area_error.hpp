#pragma once
// The exact area error (Eq. 4.2-4.3 of 002_d776f0f2af43efa4.txt, generalised; docs/area-error.md): the area
// enclosed between the tool-centre path and the quasi-static path of the machine, the polyline of radial
// segments and arcs about the machine pole through the grid nodes the tape visits. Exact up to rounding (the
// contour is the digitizer's polar track, accurate to rounding; the sector integrals are exact series).
//
// Feed it the steps of any polar tape, whatever rule made it: as a StepSink during digitize(), or from a
// TapeReader. Steps are recorded relative to the start node; finish() takes the start node and computes.
// A meter can be reset and reused; it keeps its storage (about 140 bytes per angular step).
#include <cstdint>
#include <vector>

#include "digitizer/digitize.hpp"
#include "digitizer/grid.hpp"
#include "digitizer/polar_track.hpp"
#include "optimize/sector_sweep.hpp"
#include "optimize/track_area.hpp"

namespace polarcam {

struct AreaErrorResult {
  double area_m2 = 0.0;
  uint64_t radial_steps = 0, angular_steps = 0;
  uint64_t sectors = 0;          // sectors (plane angle intervals of one angular step) holding part of the cycle
  uint64_t general_sectors = 0;  // of which were computed by the general sweep (ends, reversals, crossings)
  double theta_shift = 0.0;      // rad added to the track's angle to put it on the tape's angular branch
};

class PolarAreaMeter final : public StepSink {
 public:
  // Binds the meter to the path's track (which must outlive finish()) and the grid of the staircase (dr, dtheta,
  // steps_per_rev); forgets recorded steps.
  void reset(const PolarTrack& track, const Grid& grid);

  void step(int axis, int dir, int64_t) override { record(axis, dir); }
  void record(int axis, int dir) {
    if (axis == kAxisRadial) {
      n_ += dir;
      ++nr_;
    } else {
      arcs_.push_back({n_, m_, -1, static_cast<int8_t>(dir)});
      m_ += dir;
    }
  }

  // The staircase starts on node (n0, m0). Throws InputError when the staircase does not follow the path (its
  // start or end is more than two grid cells from the path's, or it leaves the path's angular range).
  AreaErrorResult finish(int64_t n0, int64_t m0);

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
    double t0, t1, l0, l1, r0, r1, A0, A1;  // in travel order
  };
  struct Visit {
    int64_t j;
    uint32_t first, count;
    int32_t next;
    int8_t sigma;  // +1 / -1 monotone in that direction, 0 reverses inside the sector
    bool full;     // monotone and from one ray of the sector to the other
    double rmin, rmax;
  };

  uint32_t key(int64_t j) const;
  void walk_contour(const sweep::Frame& fr);
  void add_sub(const Sub& s, int64_t j);
  void close_visit();
  void add_connector(Vec2 a, double ga, Vec2 b, double gb);
  double fast_visit(const Visit& v, double rho) const;

  const PolarTrack* track_ = nullptr;
  Grid grid_;
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

}  // namespace polarcam
