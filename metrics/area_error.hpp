#pragma once
// The exact area error (Eq. 4.2-4.3 of A. Fahim's thesis (1983), generalised; docs/area-error.md): the area
// enclosed between the tool-centre path and the quasi-static path of the machine, the polyline of radial
// segments and arcs about the machine pole through the grid nodes the tape visits. Exact up to rounding (the
// contour is the digitizer's polar track, accurate to rounding; the sector integrals are exact series).
//
// Feed it the steps of any polar tape, whatever rule made it: as a StepSink during digitize(), or from a
// TapeReader. Two modes:
//  - recorded: steps are recorded relative to the start node (about 140 bytes per angular step); finish() takes
//    the start node and computes;
//  - streamed (begin() with the start node before the first step): each sector is measured as soon as the
//    staircase and the contour have both moved more than kStreamWindow sectors away from it (the contour is
//    walked alongside the steps), so the state is a window of sectors, not the tape. Should the staircase or the
//    contour come back to a sector already measured (a tape that wanders far from its path, a contour that covers
//    the same angles again, as a spiral does), the meter stops streaming and finish() reports streamed() false:
//    the caller replays the steps in the recorded mode. Both modes give the same numbers.
// A meter can be reset and reused; it keeps its storage.
//
// The work is done by StairAreaMeter, which measures any staircase of steps of a height axis (radial, y) and an
// abscissa axis (angular, x) against a track seen through sweep::TrackView; the Cartesian meter
// (cartesian_error.hpp) is the same machine on strips of x instead of sectors of theta.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "digitizer/digitize.hpp"
#include "digitizer/grid.hpp"
#include "digitizer/polar_track.hpp"
#include "metrics/area_roots.hpp"
#include "metrics/sector_sweep.hpp"
#include "metrics/track_area.hpp"
#include "metrics/track_view.hpp"

namespace polarcam {

// Streamed area meters measure a sector once both the staircase and the contour are this many sectors away.
inline constexpr uint32_t kStreamWindow = 64;

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
    if (stream_)
      stream_run(dir);
    else
      arcs_.push_back({n_, m_, -1, static_cast<int8_t>(dir)});
    m_ += dir;
    ++nrun_;
  }

  // Streams from here on: the staircase starts on node (h0, g0). Call after reset(), before the first step;
  // finish() must then be given the same node. Without it, the meter records.
  void begin(int64_t h0, int64_t g0);

  // The staircase starts on node (h0, g0) (height index, abscissa index). Throws InputError when it does not
  // follow the path (its start or end is more than two grid cells from the path's, or it leaves the path's
  // abscissa range).
  StairAreaResult finish(int64_t h0, int64_t g0);

  // After finish() in the streamed mode: false when the staircase or the contour came back to a sector already
  // measured, and the result is void; replay the steps into a recording meter.
  bool streamed() const { return !failed_; }

  // Sectors (or strips) held at once in the streamed mode, at most, so far (testing, benchmarks).
  size_t peak_window() const { return peak_slots_; }

  // Testing: compute every sector with the general sweep.
  void set_force_general(bool on) { force_general_ = on; }

  // Instead of steps: the staircase the digitizer makes of the track with the nearest rule from node (h0, g0) (its
  // start node), read off the walk of the contour (docs/area-error.md, "The nearest staircase without the
  // digitizer"): each angular step is the crossing of a half level of the abscissa, and the radial node there is
  // the nearest one to the path. Call after reset(), with no step recorded; then finish(h0, g0) measures it as
  // if its steps had been recorded. False where a decision lies within `margin` grid units (plus rounding) of a
  // level, so that the digitizer might take it the other way: nothing is recorded then (reset() and record the
  // digitizer's steps).
  bool imply_nearest(int64_t h0, int64_t g0, double margin = kImplyMargin);
  static constexpr double kImplyMargin = 1e-7;

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

  struct Neumaier {
    double s = 0.0, c = 0.0;
    void add(double x) {
      const double t = s + x;
      c += std::abs(s) >= std::abs(x) ? (s - t) + x : (x - t) + s;
      s = t;
    }
    double value() const { return s + c; }
  };
  // One sector's strands, in the order the recorded mode lists them (the latest first).
  struct SectorIn {
    std::vector<const Visit*> vs;
    std::vector<const ArcRec*> as;
    std::vector<const sweep::Strand*> extra;
    const std::vector<Sub>* subs = nullptr;
    bool forced = false;
  };
  // A sector being gathered in the streamed mode.
  struct Slot {
    uint32_t key = 0;
    std::vector<Visit> visits;
    std::vector<Sub> subs;
    std::vector<ArcRec> arcs;
    std::vector<sweep::Strand> extra;
    bool forced = false;
  };
  // The open sectors' slots by key: open addressing with linear probing on a power-of-two table at most half full,
  // Fibonacci hashing (the keys held at once are runs of consecutive sectors, which it scatters); deletion by
  // backward shift keeps every probe run unbroken. In front of it a direct-mapped table by the key's low bits
  // holds every key whose cell is free when it comes, which in the common case (a window of consecutive sectors
  // narrower than the table) is every key: one load a lookup.
  class SlotIndex {
   public:
    static constexpr uint32_t kNone = 0xffffffffu;  // no key (keys are below 2^31)
    static constexpr uint32_t kDirect = 1024;       // cells of the direct-mapped table
    SlotIndex() { dkeys_.fill(kNone); }
    void clear();
    size_t size() const { return dsize_ + size_; }
    uint32_t find(uint32_t k) const {  // the slot of k, or kNone
      const uint32_t d = k & (kDirect - 1);
      if (dkeys_[d] == k) return dvals_[d];
      if (size_ == 0) return kNone;
      for (size_t i = home(k);; i = (i + 1) & mask_) {
        if (keys_[i] == k) return vals_[i];
        if (keys_[i] == kNone) return kNone;
      }
    }
    void insert(uint32_t k, uint32_t slot) {  // k not present
      const uint32_t d = k & (kDirect - 1);
      if (dkeys_[d] == kNone) {
        dkeys_[d] = k;
        dvals_[d] = slot;
        ++dsize_;
        return;
      }
      probe_insert(k, slot);
    }
    void erase(uint32_t k) {  // k present
      const uint32_t d = k & (kDirect - 1);
      if (dkeys_[d] == k) {
        dkeys_[d] = kNone;
        --dsize_;
        return;
      }
      probe_erase(k);
    }
   private:
    size_t home(uint32_t k) const { return (k * 0x9E3779B1u) >> shift_bits_; }
    void probe_insert(uint32_t k, uint32_t slot);
    void probe_erase(uint32_t k);
    std::array<uint32_t, kDirect> dkeys_, dvals_;
    size_t dsize_ = 0;
    std::vector<uint32_t> keys_, vals_;
    size_t mask_ = 0, size_ = 0;
    int shift_bits_ = 32;
  };
  // Keys in the order they came: a ring that grows by doubling (a queue without a deque's blocks).
  class KeyRing {
   public:
    bool empty() const { return n_ == 0; }
    uint32_t front() const { return buf_[head_]; }
    void pop_front() {
      head_ = (head_ + 1) & (buf_.size() - 1);
      --n_;
    }
    void push_back(uint32_t k) {
      if (n_ == buf_.size()) grow();
      buf_[(head_ + n_) & (buf_.size() - 1)] = k;
      ++n_;
    }
    void clear() { head_ = n_ = 0; }
   private:
    void grow();
    std::vector<uint32_t> buf_;
    size_t head_ = 0, n_ = 0;
  };
  // The walk of the contour sector by sector, resumable (the streamed mode walks it alongside the steps).
  struct WalkPt {
    double t, g, h, A;
  };
  // A stretch [ta, tb] of a segment of the walk holding its edges j0..j1-1 (ga, gb: the abscissa, in grid units,
  // at its ends).
  struct Span {
    double ta, tb, ga, gb;
    int64_t j0, j1;
    int depth;
  };
  struct Walk {
    bool done = true;
    size_t piece = 0, seg = 0;
    std::vector<double> ts;
    WalkPt cur{}, nxt{};
    int dir = 0;
    int64_t first = 0, last = 0, count = 0, q = 0;
    // the segment's stretches still to do (the next on top), and the edges of the one done
    std::vector<Span> spans;
    std::vector<WalkPt> buf;
    size_t bpos = 0;
    // buf[jump] ends a run of columns walk_fit measured at once (dense): the walk moves there, jump_q edges on
    size_t jump = std::numeric_limits<size_t>::max();
    int64_t jump_q = 0;
    double tol[3] = {0, 0, 0};  // the fits' tolerances in t, h and Astar on this piece
    std::vector<double> z, r[4];  // walk_fit: the edges' z, the series' values there (and the half levels')
  };

  uint32_t key(int64_t j) const;
  void set_shift(int64_t g0);
  void set_range();  // throws InputError
  void walk_start();
  bool walk_next();  // one sub (or none) further; false at the end
  void walk_piece_start();
  void walk_segment_start();
  WalkPt walk_at(double t) const;
  int64_t walk_level(int64_t q) const { return walk_.dir > 0 ? walk_.first + q : walk_.last - q; }
  // The edges of the segment's next stretch into walk_.buf: a stretch of many edges from fits of t, the radius
  // and Astar as series of the abscissa (walk_fit; false where a fit is refused, and the stretch is halved), a
  // short one by Newton's method on the abscissa's series edge by edge (walk_solve).
  void walk_refill();
  bool walk_fit(const Span& s);
  void walk_solve(const Span& s);
  void walk_emit(const WalkPt& a, const WalkPt& b);
  // imply_nearest: the half levels of the abscissa a stretch crosses, in travel order (ga < L <= gb going up,
  // gb < L <= ga going down), each an angular step at the radial node nearest the path there (imply_arc); h_at
  // gives the radius at a batch of them (imply_levels)
  template <class HAt>
  void imply_levels(const Span& s, HAt&& h_at);
  const std::vector<double>& half_levels(const Span& s);  // the half levels of a stretch, in the walk's order
  void imply_solve(const Span& s);  // the same, each crossing solved by Newton's method on the abscissa's series
  void imply_arc(double h);  // the angular step at a half level, the radius there h
  void imply_point(const WalkPt& p);  // a segment's end: its radial steps, and the margins of its values
  // the node nearest f (floor(f + 1/2)) into n; false where f lies within the margin of a half level or is not a
  // node (not finite, or beyond 4e18 steps; n is then left as it was)
  bool nearest_node(double f, int64_t& n) const;
  void add_sub(const Sub& s, int64_t j, int8_t sigma, double hmin, double hmax);  // its direction, radial range
  void close_visit();
  void add_connector(Vec2 a, double ga, Vec2 b, double gb);
  double fast_visit(const Sub* subs, size_t count, double rho, double jd) const;  // a visit's parts, summed
  // a visit of these first and last subs, monotone in direction sigma (0: it reverses), runs from one side of its
  // sector to the other
  static bool full_visit(int8_t sigma, const Sub& first, const Sub& last);
  // the integral of the staircase's level rho minus a piece's base ha, per unit of lambda
  double level_factor(double ha, double rho) const;
  // a sub's part against the level rho (split where the path crosses it), and the start of the crossing's search
  double sub_part(const Sub& b, double rho, double jd) const;
  void start_crossing(const Sub& b, double rho, area_roots::RadiusCrossing& c) const;
  // A visit's part of the area, in the order of the sectors: a visit of one sub that crosses its level waits for a
  // second, and the two crossings are found side by side (radius_crossing2); the values wait with them, so the sum
  // takes them in the same order (the same bytes as fast_visit one by one).
  void add_visit(const Visit& v, double rho, const std::vector<Sub>& subs);
  void add_one(const Sub& b, double rho, int64_t j);  // add_visit of a visit of one sub
  void add_total(double x);
  void flush_pending();
  // the part of a sub crossing its level rho where the path's abscissa and area are g and a
  double crossed_part(const Sub& b, double rho, double jd, double g, double a) const;
  // The common case of a sector: one pass of the contour, monotone from one side to the other in the direction of
  // the one level strand (fast_visit); false, with nothing added, where the sector needs more.
  bool one_pass(const Visit& v, const ArcRec& a, const std::vector<Sub>& subs);
  void add_sector(SectorIn& in, StairAreaResult& res);
  Vec2 node_point(int64_t h, int64_t g) const;
  Vec2 path_point(double h, double g) const;
  // streamed mode
  void stream_run(int dir);
  // nullptr (and failed_) when the sector was measured already; ordered: in order_ (a slot that takes the place of
  // an entry of the one-pass queue keeps the entry's)
  Slot* slot(uint32_t k, bool ordered = true);
  Slot* stream_slot(uint32_t k);  // slot(k), after moving a lane entry of k into it
  bool pinned(uint32_t k) const;
  void evict(bool all);
  void finalize(uint32_t slot_index);
  bool finalized(uint32_t k) const;
  void mark_finalized(uint32_t k);
  uint64_t key_distance(uint32_t a, uint32_t b) const;

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
  uint32_t open_slot_ = 0;  // streamed: the slot holding the visit being built
  Walk walk_;
  std::unique_ptr<sweep::SectorSolver> solver_;
  sweep::Frame frame_{};
  Neumaier total_;
  struct Crossing {
    Sub b;
    double rho, jd;
    uint32_t key = 0;  // dense_crossing: the sector's key
  };
  // dense_crossing's batch (at most crossing_batch(), four)
  Crossing dense_x_[4];
  size_t dense_n_ = 0;
  struct Pending {
    double value;
    int32_t crossing;  // >= 0: the value is that crossing's part
  };
  std::vector<Pending> pending_;
  std::vector<Crossing> crossings_;
  // the pair of pieces whose series pair_series_ holds
  static constexpr uint32_t kNoPiece = 0xffffffffu;
  uint32_t pair_[2] = {kNoPiece, kNoPiece};
  area_roots::PairSeries pair_series_;
  uint32_t quad_[4] = {kNoPiece, kNoPiece, kNoPiece, kNoPiece};  // the four pieces whose series quad_series_ holds
  area_roots::QuadSeries quad_series_;
  size_t fit_piece_ = SIZE_MAX;  // the piece whose G, H and Astar fit_series_ holds (walk_fit's samples)
  area_roots::QuadSeries fit_series_;
  StairAreaResult sres_;  // streamed: sectors measured so far
  // imply_nearest: on while its walk runs; failed when a decision was too near a level; walked when finish() finds
  // the walk done (visits and level strands); n the radial node at the last point; the margin in grid units
  struct Implied {
    bool on = false, failed = false, walked = false;
    int64_t n = 0, h0 = 0, g0 = 0;
    double margin = 0.0, inv_height = 0.0;
    std::vector<double> L, z, h;  // a stretch's half levels, their z, their radii
    std::vector<double> rho;      // the levels of a dense stretch's columns
    // dense: the path's angle is monotone and no sector is visited twice, so a sector's one full visit and its one
    // level strand are measured as the walk leaves it (dense_close), not listed for finish()
    bool dense = false;
    int dir = 0;  // the path's direction in angle
    struct Arc {
      int64_t n, m, j;  // the node before the step (relative to the start, as run() records it), the sector
      int8_t dir;
    };
    std::vector<Arc> arcs;  // level strands waiting for their sector's visit, from `head` on
    size_t head = 0;
    bool open = false;  // the visit being gathered
    int64_t j = 0;
    int8_t sigma = 0;
    double hmin = 0, hmax = 0;
    std::vector<Sub> subs;
    std::vector<double> part;  // by key: the dense sectors' parts (NaN: none)
  };
  Implied imp_;
  // imply_nearest's test for the dense walk: the path's direction in angle, 0 where it turns back or may visit a
  // sector twice
  int path_direction() const;
  void dense_sub(const Sub& s, int64_t j, int8_t sigma, double lo, double hi);
  void dense_close();
  // a sector's visit (its subs, direction and radial range): measured with its one level strand where it is the
  // fast path's one pass, otherwise listed with its level strands for finish()
  void dense_visit(const Sub* subs, size_t count, int64_t j, int8_t sigma, double hmin, double hmax);
  bool dense_full(const Sub& s, int64_t j, int8_t sigma);  // walk_emit's usual sub, measured at once
  // the part of a sector's one pass against its level strand (dense_visit, dense_full)
  void dense_part(const Sub* subs, size_t count, const Implied::Arc& arc, int64_t j);
  void dense_crossing(const Sub& b, double rho, double jd, uint32_t k);
  void dense_flush();
  // the parts of two crossings found side by side (flush_pending, dense_crossing)
  void crossing_pair(const Crossing& x0, const Crossing& x1, double part[2]);
  // the same for four, on the four lanes of an AVX vector (dense_flush, where area_roots::has_avx())
  void crossing_quad(const Crossing* x, double part[4]);
  // the parts of up to four crossings (a batch of flush_pending or dense_flush): four side by side, pairs, then one
  void crossing_parts(const Crossing* x, size_t count, double part[4]);
  static size_t crossing_batch();  // crossings gathered before they are found together: 4 with AVX, else 2
  void prepare_recorded();  // finish()'s state for the recorded mode (range, heads, lists)

  // streamed mode
  bool stream_ = false, failed_ = false;
  int64_t h0_ = 0, g0_ = 0;
  uint64_t nrun_ = 0, subs_out_ = 0;
  std::string range_error_;  // the first angular step that left the path's range (thrown by finish())
  SlotIndex slot_of_;
  std::vector<Slot> slots_;
  std::vector<uint32_t> free_slots_;
  KeyRing order_;  // keys in the order their slots (or one-pass entries) were opened, with kPinned, kPass
  std::map<uint32_t, uint32_t> done_;  // measured keys: disjoint ranges [first, last], but the run below
  uint32_t done_lo_ = 1, done_hi_ = 0;  // the least and the largest measured key (none: lo > hi)
  uint32_t run_lo_ = 1, run_hi_ = 0;    // the range being extended, key by key, not yet in done_ (none: lo > hi)
  void flush_run();                     // the run into done_
  static constexpr uint32_t kPinned = 0x80000000u;  // in order_: the key is pinned (keys are below 2^31)
  // in order_: an entry of the one-pass queue (the queue is on only where every key is below kPass)
  static constexpr uint32_t kPass = 0x40000000u;
  std::vector<uint32_t> pinned_;  // keys about the start and end (connectors): measured at finish()
  uint32_t pins_[3] = {0, 0, 0};
  std::array<uint32_t, 2> pin_iv_[6] = {};  // the keys pinned(): npin_iv_ intervals [first, last]
  size_t npin_iv_ = 0;
  mutable std::array<uint32_t, 2> pin_near_ = {1, 0};  // keys known to share pin_near_val_ (pinned()'s last answer)
  mutable bool pin_near_val_ = false;
  void set_pins();  // pin_iv_ from pins_
  uint32_t stair_key_ = 0, walk_key_ = 0;
  SectorIn sector_in_;
  std::vector<sweep::Strand> strands_;
  size_t peak_slots_ = 0;
  // The streamed mode's one-pass queue (docs/area-error.md, "The one-pass queue"): a sector the walk crosses in one
  // sub, from ray to ray, with no strand before it and away from the pins, is an entry of a queue in the walk's
  // order with room for one level strand, not a slot. It takes its place in order_ and is measured as a slot would
  // be; anything more in it (a second strand or visit, a connector) moves it into a slot first.
  struct PassEnt {
    Sub sub;
    int64_t j, arc_n;
    uint32_t key;
    int8_t sigma, narcs, arc_dir;
    bool dead;  // moved into a slot
  };
  static constexpr uint32_t kPassDirect = 1024;  // the queue's direct-mapped index by the key's low bits
  bool pass_on_ = false;
  std::vector<PassEnt> pass_;  // a ring of power-of-two size: the entry of sequence number q at q & (size - 1)
  uint64_t pass_seq0_ = 0;     // the head's sequence number
  size_t pass_n_ = 0;
  std::array<uint32_t, kPassDirect> pass_key_{};  // the key of the live entry in each cell (SlotIndex::kNone: none)
  std::array<uint64_t, kPassDirect> pass_seq_{};  // its sequence number
  void pass_clear();
  PassEnt* pass_find(uint32_t k);
  bool pass_sub(const Sub& s, int64_t j, int8_t sigma, uint32_t k);  // false: not a queue entry
  void pass_promote(PassEnt& e);  // into a slot
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
  // Streams (StairAreaMeter::begin): the staircase starts on node (n0, m0). Named apart from StepSink::begin,
  // which the digitizer calls on every sink: a meter streams only when its owner asks it to.
  void stream_from(int64_t n0, int64_t m0) { core_.begin(n0, m0); }
  // StairAreaMeter::imply_nearest: the nearest rule's staircase from the start node (n0, m0) (start_node()), made
  // from the track; then finish(n0, m0). False: nothing recorded; reset() and digitize into the meter.
  bool imply_nearest(int64_t n0, int64_t m0) { return core_.imply_nearest(n0, m0); }
  bool streamed() const { return core_.streamed(); }
  size_t peak_window() const { return core_.peak_window(); }

 private:
  Grid grid_;
};

}  // namespace polarcam
