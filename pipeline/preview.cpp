#include "pipeline/preview.hpp"

#include <cmath>

#include "cam/error.hpp"
#include "digitizer/replay.hpp"
#include "digitizer/tape.hpp"
#include "pipeline/job_tape.hpp"

namespace polarcam {
namespace {

// Keeps a node walk as polylines of points at least `res` apart (and always the last one), one a run of the tool
// down or up; a new run starts at the last point of the one before.
class Runs {
 public:
  Runs(Preview& pv, double res) : pv_(pv), res2_(res * res) {}
  void add(double x, double y) {
    last_[0] = x, last_[1] = y, pending_ = true, any_ = true;
    if (!cur_.x.empty()) {
      const double dx = x - cur_.x.back(), dy = y - cur_.y.back();
      if (dx * dx + dy * dy < res2_) return;
    }
    cur_.x.push_back(x);
    cur_.y.push_back(y);
    pending_ = false;
  }
  void tool(bool down) {
    finish();
    down_ = down;
    if (any_) add(last_[0], last_[1]);
  }
  void finish() {
    if (pending_) cur_.x.push_back(last_[0]), cur_.y.push_back(last_[1]);
    pending_ = false;
    if (!cur_.x.empty()) (down_ ? pv_.stepped : pv_.rapids).push_back(std::move(cur_));
    cur_ = Polyline{};
  }
  double last_x() const { return last_[0]; }
  double last_y() const { return last_[1]; }

 private:
  Preview& pv_;
  double res2_;
  Polyline cur_;
  double last_[2] = {0, 0};
  bool pending_ = false, any_ = false, down_ = true;
};

// The machine's position at node (n, m): a coupled arm's radial motor stands at q = r + c theta.
struct NodeMap {
  double dr, dtheta, c;
  void xy(const int64_t node[2], double& x, double& y) const {
    const double th = static_cast<double>(node[1]) * dtheta;
    const double r = static_cast<double>(node[0]) * dr - c * th;
    x = r * std::cos(th) * 1e3;
    y = r * std::sin(th) * 1e3;
  }
};

// Follows the nodes of a job's tape from its start (StepSink::begin) into the runs.
class NodeSink : public StepSink {
 public:
  NodeSink(const NodeMap& map, Runs& th) : map_(map), th_(th) {}
  void begin(int64_t n, int64_t m) override {
    node_[0] = n, node_[1] = m;
    double x, y;
    map_.xy(node_, x, y);
    th_.add(x, y);
  }
  void step(int axis, int dir, int64_t) override {
    node_[axis] += dir;
    ++steps;
    double x, y;
    map_.xy(node_, x, y);
    th_.add(x, y);
  }
  void tool(bool down, int64_t) override { th_.tool(down); }
  uint64_t steps = 0;

 private:
  const NodeMap& map_;
  Runs& th_;
  int64_t node_[2] = {0, 0};
};

// Samples a track's pieces into the tool path's polyline (16 points a piece and the end) and the slowed stretches.
class PathSampler {
 public:
  PathSampler(Preview& pv, double rc, size_t pieces) : pv_(pv), rc_(rc), path_(pv.path.emplace_back()) {
    path_.x.reserve(16 * pieces + 1);
    path_.y.reserve(16 * pieces + 1);
  }
  void piece(const TrackPiece& p) {
    for (int k = 0; k < 16; ++k) {
      const double t = -1.0 + 2.0 * k / 16.0;
      const double r = p.q_a[0] + p.Q[0](t), theta = p.q_a[1] + p.Q[1](t);
      const double x = r * std::cos(theta) * 1e3, y = r * std::sin(theta) * 1e3;
      path_.x.push_back(x);
      path_.y.push_back(y);
      double dr, dth;
      double f;
      p.Q[0].eval2(t, f, dr);
      p.Q[1].eval2(t, f, dth);
      const double ds2 = dr * dr + r * r * dth * dth;
      const bool slow = r < rc_ && ds2 < 0.99 * 0.99 * (dr * dr + rc_ * rc_ * dth * dth);
      if (slow) {
        if (!in_slow_) pv_.slowed.emplace_back();
        pv_.slowed.back().x.push_back(x);
        pv_.slowed.back().y.push_back(y);
      }
      in_slow_ = slow;
    }
    end_r_ = p.q_a[0] + p.Q[0](1.0);
    end_theta_ = p.q_a[1] + p.Q[1](1.0);
  }
  void finish() {
    path_.x.push_back(end_r_ * std::cos(end_theta_) * 1e3);
    path_.y.push_back(end_r_ * std::sin(end_theta_) * 1e3);
  }

 private:
  Preview& pv_;
  double rc_;
  Polyline& path_;
  bool in_slow_ = false;
  double end_r_ = 0.0, end_theta_ = 0.0;
};

}  // namespace

Preview preview_job(const Job& job, double resolution_mm, DigitizedJob* digitized) {
  Preview pv;
  pv.title = job.contour->name();
  pv.r_min_mm = job.machine.grid.r_min * 1e3;
  if (job.machine.grid.r_max) pv.r_max_mm = *job.machine.grid.r_max * 1e3;
  // one pass of the digitizer into the node walk (its start node comes with StepSink::begin)
  const NodeMap map{job.machine.grid.dr, job.machine.grid.dtheta, job.machine.coupling};
  Runs th(pv, resolution_mm);
  NodeSink sink(map, th);
  DigitizedJob d = digitize_job(job, &sink);
  th.finish();
  pv.steps = sink.steps;
  // the tool path, and where the tool is slower than asked: the timing radius r_c near the centre of a theta-rho
  // path (docs/patterns.md) scales the speed by |P'| / sqrt(r'^2 + r_c^2 theta'^2) where r < r_c
  const double rc = job_theta_rho_path(*d.path) ? job_timing_radius(job) : 0.0;
  auto draw = [&](const PolarTrack& tr) {
    PathSampler ps(pv, rc, tr.pieces().size());
    for (const TrackPiece& p : tr.pieces()) ps.piece(p);
    ps.finish();
  };
  if (d.lifted) {
    for (const PolarTrack& t : d.lifted->tracks) draw(t);
  } else if (d.polyline) {
    // the polar track's pieces (r, theta), made again from the vertices
    PathSampler ps(pv, rc, d.polyline->size());
    d.polyline->for_each([&](size_t, const TrackPiece& p) { ps.piece(p); }, true);
    ps.finish();
  } else {
    draw(d.track);
  }
  pv.start[0] = pv.path.front().x.front(), pv.start[1] = pv.path.front().y.front();
  pv.end[0] = pv.path.back().x.back(), pv.end[1] = pv.path.back().y.back();
  if (digitized) *digitized = std::move(d);
  return pv;
}

Preview preview_tape(const std::string& path, double resolution_mm) {
  TapeReader rd(path);
  const TapeHeader& h = rd.header();
  if (h.axes != TapeAxes::polar) throw InputError("preview draws polar tapes; this one is Cartesian", path);
  Preview pv;
  pv.title = std::filesystem::path(path).filename().string();
  pv.r_min_mm = h.r_min * 1e3;
  if (h.has_r_max) pv.r_max_mm = h.r_max * 1e3;
  // the coupling of a sand-table arm, from the machine the provenance records
  const double c = tape_coupling_steps_per_rev(h) * h.res[0] / (2.0 * M_PI);
  const NodeMap map{h.res[0], h.res[1], c};
  Runs th(pv, resolution_mm);
  if (h.tool_starts_up) th.tool(false);
  rd.on_tool_event([&](const ToolEvent& e) { th.tool(e.down); });
  TapeReplay rp(rd);
  double x, y;
  map.xy(h.start, x, y);
  th.add(x, y);
  pv.start[0] = x, pv.start[1] = y;
  MachineStep s;
  while (rp.next(s)) {
    map.xy(s.node, x, y);
    th.add(x, y);
    ++pv.steps;
  }
  th.finish();
  pv.end[0] = th.last_x(), pv.end[1] = th.last_y();
  return pv;
}

}  // namespace polarcam
