#include "machine/player/play_plan.hpp"
#include "machine/player/int128.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cam/error.hpp"

namespace polarcam {
namespace {

std::string num(double v, int digits = 6) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

bool same(double a, double b) { return std::fabs(a - b) <= 1e-9 * std::max(std::fabs(a), std::fabs(b)); }

}  // namespace

PlayMachine machine_from_header(const TapeHeader& h) {
  PlayMachine m;
  m.source = "the tape's work area";
  m.grid.dr = h.res[0];
  m.grid.dtheta = h.res[1];
  m.grid.steps_per_rev = h.steps_per_rev;
  m.grid.r_min = h.r_min;
  if (h.has_r_max) m.grid.r_max = h.r_max;
  if (h.has_theta_range) {
    m.grid.theta_min = h.theta_min;
    m.grid.theta_max = h.theta_max;
  }
  return m;
}

PlayPlan plan_playback(const std::string& tape, const PlayScaling& sc, const std::optional<PlayMachine>& machine) {
  PlayPlan p;
  p.tape = tape;
  p.scaling = sc;
  p.header = verify_tape(tape);  // the whole tape, checksums and totals, before anything else
  const TapeHeader& h = p.header;
  if (h.axes != TapeAxes::polar) throw InputError("a Cartesian tape; the player drives polar machines", tape);
  const PlayMachine m = machine ? *machine : machine_from_header(h);
  if (machine) {
    if (!same(m.grid.dr, h.res[0]) || !same(m.grid.dtheta, h.res[1]))
      throw InputError("made for another machine grid (dR = " + num(h.res[0] * 1e3) + " mm, dtheta = " +
                       num(h.res[1]) + " rad, " + std::to_string(h.steps_per_rev) + " steps/rev) than " + m.source +
                       " (dR = " + num(m.grid.dr * 1e3) + " mm, dtheta = " + num(m.grid.dtheta) + " rad, " +
                       std::to_string(m.grid.steps_per_rev) + " steps/rev)", tape);
  }
  const Ratio size = sc.size;
  const bool spread = size.num > size.den;  // one tape step may give several machine steps
  // a sand-table arm's tape: its radial index is the radial motor's, q0 = r + c theta (c radial steps per angular
  // step), so the ball's radius is q0 - c theta; scaling q0 or turning the arm would not scale or turn the drawing
  const double coupling = tape_coupling_steps_per_rev(h);
  const double k_couple = coupling != 0.0 && h.steps_per_rev > 0 ? coupling / static_cast<double>(h.steps_per_rev) : 0.0;
  if (coupling != 0.0) {
    if (size.num != size.den)
      throw InputError("scales the radial motor, which on this sand-table arm also follows the arm's turning (" +
                           num(coupling) + " steps a turn): the drawing would be distorted, not scaled",
                       "--size-scale");
    if (sc.angle_offset != 0)
      throw InputError("turns the arm, which on this sand-table arm also moves the ball along it (" + num(coupling) +
                           " radial steps a turn): the drawing would be distorted, not turned",
                       "--angle-offset");
  }

  int64_t n = h.start[0];
  int64_t N = scaled_radial_index(n, size);
  int64_t M = h.start[1] + sc.angle_offset;
  p.start[0] = N;
  p.start[1] = M;
  p.lo[0] = p.hi[0] = N;
  p.lo[1] = p.hi[1] = M;
  // the ball's radius in radial steps (the radial index itself on a plain polar machine)
  double ball_lo = static_cast<double>(N) - k_couple * static_cast<double>(M), ball_hi = ball_lo;
  p.steps.reserve(h.record_count + (spread ? (h.plus[0] + h.minus[0]) * static_cast<uint64_t>(size.num / size.den) : 0));

  std::vector<PlayStep> pending;  // angular steps since the last radial tape step (size scale > 1 only)
  auto emit = [&](const PlayStep& s) {
    p.steps.push_back(s);
    int64_t& node = s.axis == 0 ? N : M;
    node += s.dir;
    p.lo[s.axis] = std::min(p.lo[s.axis], node);
    p.hi[s.axis] = std::max(p.hi[s.axis], node);
    ++p.steps_per_axis[s.axis];
    if (k_couple != 0.0) {
      const double ball = static_cast<double>(N) - k_couple * static_cast<double>(M);
      ball_lo = std::min(ball_lo, ball);
      ball_hi = std::max(ball_hi, ball);
    }
  };

  TapeReader rd(tape);
  StepRecord r;
  uint64_t t = 0, t_radial = 0, rec = 0;
  if (h.event_count > 0) {
    p.tools.push_back(PlayTool{0, 0, !h.tool_starts_up});
    // an event is a boundary: the machine steps before it are emitted before it, and a radial tape step after it
    // spreads its machine steps (size scale > 1) over the time after it only
    rd.on_tool_event([&](const ToolEvent& e) {
      for (const PlayStep& s : pending) emit(s);
      pending.clear();
      t_radial = std::max(t_radial, e.t_ticks);
      p.tools.push_back(PlayTool{e.t_ticks, p.steps.size(), e.down});
    });
  }
  while (rd.next(r)) {
    t += r.interval;
    ++rec;
    if (r.axis == 1) {
      PlayStep s{t, rec, 1, static_cast<int8_t>(r.dir)};
      if (spread) pending.push_back(s);
      else emit(s);
      continue;
    }
    const int64_t n_new = n + r.dir;
    const int64_t N_new = scaled_radial_index(n_new, size);
    const int64_t k = std::llabs(N_new - scaled_radial_index(n, size));
    const int8_t d = N_new > scaled_radial_index(n, size) ? 1 : -1;
    // k machine steps spread evenly over (t_radial, t]: the j-th at t_radial + floor((t - t_radial) j / k)
    size_t a = 0;
    for (int64_t j = 1; j <= k; ++j) {
      const uint64_t tj = t_radial + static_cast<uint64_t>((static_cast<u128>(t - t_radial) * static_cast<uint64_t>(j)) /
                                                             static_cast<uint64_t>(k));
      while (a < pending.size() && pending[a].t <= tj) emit(pending[a++]);
      emit(PlayStep{tj, rec, 0, d});
    }
    while (a < pending.size()) emit(pending[a++]);
    pending.clear();
    n = n_new;
    t_radial = t;
  }
  for (const PlayStep& s : pending) emit(s);
  p.end[0] = N;
  p.end[1] = M;

  // work area: every node the machine stands on, within half a resolution of the area (the nearest-node tolerance)
  const Grid& g = m.grid;
  const std::string scale_note = " with size scale " + to_string(size) + " and angle offset " + std::to_string(sc.angle_offset);
  if (k_couple != 0.0) {
    // the work area bounds the ball's radius; the radial motor has no travel of its own to bound (as digitize).
    // The nearest node of q0 is within half a radial step of it, and the angle within half an angular step, which
    // moves the ball by half of c angular steps: the tolerance is their sum.
    const double r_lo = ball_lo * g.dr, r_hi = ball_hi * g.dr, slack = 0.5 * g.dr * (1.0 + std::abs(k_couple));
    if (r_lo < g.r_min - slack)
      throw InputError("leaves the work area: the ball's radius falls to " + num(r_lo * 1e3) + " mm < r_min " +
                       num(g.r_min * 1e3) + " mm of " + m.source, tape);
    if (g.r_max && r_hi > *g.r_max + slack)
      throw InputError("leaves the work area: the ball's radius reaches " + num(r_hi * 1e3) + " mm > r_max " +
                       num(*g.r_max * 1e3) + " mm of " + m.source, tape);
  } else {
    const double r_lo = static_cast<double>(p.lo[0]) * g.dr, r_hi = static_cast<double>(p.hi[0]) * g.dr;
    if (p.lo[0] < 0 || r_lo < g.r_min - 0.5 * g.dr)
      throw InputError("leaves the work area" + scale_note + ": r falls to " + num(r_lo * 1e3) + " mm (node " +
                       std::to_string(p.lo[0]) + ") < r_min " + num(g.r_min * 1e3) + " mm of " + m.source, tape);
    if (g.r_max && r_hi > *g.r_max + 0.5 * g.dr)
      throw InputError("leaves the work area" + scale_note + ": r reaches " + num(r_hi * 1e3) + " mm (node " +
                       std::to_string(p.hi[0]) + ") > r_max " + num(*g.r_max * 1e3) + " mm of " + m.source, tape);
  }
  if (g.theta_min) {
    const double th_lo = static_cast<double>(p.lo[1]) * g.dtheta, th_hi = static_cast<double>(p.hi[1]) * g.dtheta;
    if (th_lo < *g.theta_min - 0.5 * g.dtheta)
      throw InputError("leaves the work area" + scale_note + ": theta falls to " + num(th_lo) + " rad (node " +
                       std::to_string(p.lo[1]) + ") < theta_min " + num(*g.theta_min) + " rad of " + m.source, tape);
    if (th_hi > *g.theta_max + 0.5 * g.dtheta)
      throw InputError("leaves the work area" + scale_note + ": theta reaches " + num(th_hi) + " rad (node " +
                       std::to_string(p.hi[1]) + ") > theta_max " + num(*g.theta_max) + " rad of " + m.source, tape);
  }
  return p;
}

PlayPlan resume_plan(const PlayPlan& plan, uint64_t done) {
  if (done == 0) return plan;
  if (done >= plan.steps.size())
    throw InputError("the tape has " + std::to_string(plan.steps.size()) +
                     " machine steps at these scales: give a step below that (the step a stopped run reached)",
                     "--resume " + std::to_string(done));
  PlayPlan r = plan;
  const uint64_t t0 = plan.steps[done - 1].t;
  for (uint64_t k = 0; k < done; ++k) r.start[plan.steps[k].axis] += plan.steps[k].dir;
  r.tools.clear();
  for (const PlayTool& e : plan.tools) {
    if (e.before <= done) {  // done or due before the resumed steps: the state the tool must be in at the start
      if (r.tools.empty()) r.tools.push_back(PlayTool{0, 0, e.down});
      r.tools.front().down = e.down;
    } else {
      r.tools.push_back(PlayTool{e.t - t0, e.before - done, e.down});
    }
  }
  r.steps.assign(plan.steps.begin() + static_cast<std::ptrdiff_t>(done), plan.steps.end());
  r.steps_per_axis[0] = r.steps_per_axis[1] = 0;
  for (PlayStep& s : r.steps) {
    s.t -= t0;
    ++r.steps_per_axis[s.axis];
  }
  return r;
}

}  // namespace polarcam
