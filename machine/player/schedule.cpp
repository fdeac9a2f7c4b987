#include "machine/player/schedule.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "machine/player/int128.hpp"
#include "machine/player/run_fit.hpp"

namespace polarcam {
namespace {

i128 floor_div(i128 a, i128 b) {  // b > 0
  i128 q = a / b;
  if (a % b != 0 && a < 0) --q;
  return q;
}
i128 ceil_div(i128 a, i128 b) {  // b > 0
  i128 q = a / b;
  if (a % b != 0 && a > 0) ++q;
  return q;
}

const char* axis_name(int a) { return a == 0 ? "radial" : "angular"; }

// Plan step i cannot be placed after the previous step of its axis (first: after the start).
InputError too_close(const PlayPlan& plan, uint64_t tick_ps, size_t i, bool first) {
  const PlayStep& s = plan.steps[i];
  const std::string what = first ? ") comes within the first controller tick after the start"
                                 : std::string(") comes less than one controller tick after the previous ") +
                                       axis_name(s.axis) + " step";
  return InputError("machine step " + std::to_string(i + 1) + " (" + axis_name(s.axis) +
                    ", from tape record " + std::to_string(s.record) + what + " at speed scale " +
                    to_string(plan.scaling.speed) + " (tick " + significant(tick_ps / 1000.0, 6) +
                    " ns): use a lower speed scale or a finer tick", plan.tape);
}

// An axis steps at most once a tick, and never at tick 0 (its first interval is at least one tick): every valid
// tick sequence in the windows is strictly increasing, so the windows of each axis can be narrowed to that.
// `index` lists the plan steps of one axis in order. The forward pass finds the first step that cannot be placed;
// after it, the backward pass cannot empty a window.
void narrow_axis(const PlayPlan& plan, uint64_t tick_ps, std::vector<StepWindow>& w, const std::vector<size_t>& index) {
  for (size_t k = 0; k < index.size(); ++k) {
    StepWindow& c = w[index[k]];
    c.lo = std::max(c.lo, k == 0 ? int64_t{1} : w[index[k - 1]].lo + 1);
    if (c.lo > c.hi) throw too_close(plan, tick_ps, index[k], k == 0);
  }
  for (size_t k = index.size(); k-- > 1;) w[index[k - 1]].hi = std::min(w[index[k - 1]].hi, w[index[k]].hi - 1);
}

std::vector<size_t> axis_steps(const PlayPlan& plan, int axis) {
  std::vector<size_t> v;
  for (size_t k = 0; k < plan.steps.size(); ++k)
    if (plan.steps[k].axis == axis) v.push_back(k);
  return v;
}

struct AxisItems {
  std::vector<QueueItem> items;
  std::vector<uint64_t> horizon, nsteps;
  void add(const QueueItem& it, uint64_t h, uint64_t n) {
    items.push_back(it);
    horizon.push_back(h);
    nsteps.push_back(n);
  }
};

// Executes `it` from `clk` with the controller's arithmetic; returns how many of its first steps land in their
// windows w[0..] (after the previous step's tick), and leaves the clock after the last of them.
uint32_t execute_checked(const QueueItem& it, const StepWindow* w, AxisClock& clk) {
  RunCursor cur;
  cur.begin(it);
  uint32_t ok = 0;
  while (cur.left > 0) {
    AxisClock c = clk;
    const uint64_t tick = c.advance(cur.next());
    if (static_cast<int64_t>(tick) < w[ok].lo || static_cast<int64_t>(tick) > w[ok].hi) break;
    clk = c;
    ++ok;
  }
  return ok;
}

// Compresses the steps of one axis (their windows, directions and plan indices) into runs and waits.
void compress_axis(const PlayPlan& plan, uint64_t tick_ps, const RunShape& shape, int axis,
                   const std::vector<StepWindow>& w, const std::vector<int8_t>& dir, const std::vector<size_t>& index,
                   AxisItems& out, Schedule& sc) {
  AxisClock clk;
  RunRef ref;
  // where each step's stretch of one direction ends (a run never turns), found once: the search for a run's
  // limit must not walk the steps ahead, or a run that ends early would cost the whole stretch
  std::vector<size_t> turn(w.size());
  for (size_t k = w.size(); k-- > 0;) turn[k] = k + 1 < w.size() && dir[k + 1] == dir[k] ? turn[k + 1] : k + 1;
  // The longest run the search may propose. The search fits in double precision and the run is then executed
  // exactly; where the rounding of the run's parameters to the wire's 2^-32 ticks spoils a long run (slow steps
  // far apart in ticks make the cubic term's rounding large), only a short prefix lands in its windows. Rather
  // than keeping that prefix and searching the same long stretch again for every step (time growing with the
  // product of steps and run length), the cap is halved and the search repeated; it doubles again after every
  // run that reached it. Each search costs time in proportion to the run it proposes, so the compression is
  // linear in the steps, whatever the ticks between them.
  uint32_t cap = kMaxRunCount;
  size_t pos = 0;
  while (pos < w.size()) {
    // long gap: wait until just under the span limit before the window
    if (w[pos].lo > static_cast<int64_t>(clk.base) + kMaxSpanTicks / 2) {
      QueueItem it;
      it.kind = ItemKind::wait;
      it.axis = static_cast<uint8_t>(axis);
      it.wait = static_cast<uint64_t>(w[pos].lo) - clk.base - kMaxSpanTicks / 4;
      clk.base += it.wait;
      out.add(it, clk.base, 0);
      ++sc.waits;
      continue;
    }
    // steps of one direction, every one within the span limit of the clock (the windows' upper ends increase
    // strictly along an axis, so the first one beyond it is found by bisection)
    const auto within_span = [&](const StepWindow& x) { return x.hi - static_cast<int64_t>(clk.base) < kMaxSpanTicks; };
    const size_t span_end = static_cast<size_t>(
        std::partition_point(w.begin() + static_cast<std::ptrdiff_t>(pos) + 1,
                             w.begin() + static_cast<std::ptrdiff_t>(turn[pos]), within_span) - w.begin());
    const uint32_t limit = static_cast<uint32_t>(std::min<size_t>(std::min<size_t>(span_end - pos, kMaxRunCount), cap));
    ++sc.searches;
    const i128 C = (static_cast<i128>(clk.base) << kFracBits) + clk.frac;
    const RunProposal p = propose_run(&w[pos], limit, C, ref, shape);
    QueueItem it;
    it.kind = ItemKind::run;
    it.axis = static_cast<uint8_t>(axis);
    it.dir = dir[pos];
    it.count = p.count;
    it.offset = p.offset;
    it.interval = p.interval;
    it.add = p.add;
    it.add2 = p.add2;
    // Execute the proposal exactly as the controller will and keep the steps that land in their windows (a
    // prefix of a valid run is a valid run with the same parameters).
    uint32_t ok = 0;
    AxisClock after = clk;
    sc.searched_steps += p.count;
    if (run_is_valid(it)) {
      ok = execute_checked(it, &w[pos], after);
      it.count = ok;
    }
    if (ok < p.count / 2) {  // rounding spoiled the run: search again for one half as long
      cap = p.count / 2;
      continue;
    }
    if (ok == limit && limit == cap) cap = static_cast<uint32_t>(std::min<uint64_t>(2 * uint64_t{cap}, kMaxRunCount));
    if (ok == 0) {
      // one step, on the first tick of its window that the clock can reach
      it.count = 1;
      it.offset = 0;
      it.interval = static_cast<int64_t>(std::max(static_cast<i128>(kOneTick), (static_cast<i128>(w[pos].lo) << kFracBits) - C));
      it.add = 0;
      it.add2 = 0;
      after = clk;
      if (!run_is_valid(it) || execute_checked(it, &w[pos], after) != 1) throw too_close(plan, tick_ps, index[pos], pos == 0);
      ok = 1;
    }
    if (!run_is_valid(it)) throw std::logic_error("step compression: invalid run");
    clk = after;
    ref = continuation(it);
    out.add(it, clk.base, ok);
    sc.steps[axis] += ok;
    sc.last_tick = std::max(sc.last_tick, clk.base);
    ++sc.runs;
    pos += ok;
  }
  QueueItem end;
  end.kind = ItemKind::end;
  end.axis = static_cast<uint8_t>(axis);
  out.add(end, UINT64_MAX, 0);
}

}  // namespace

// ------------------------------------------------------------------------------------------- windows

uint64_t tool_dwell_ticks(const PlayPlan& plan, uint64_t tick_ps) {
  if (plan.tools.empty() || !(plan.tool_dwell_s > 0)) return 0;
  const double d = std::ceil(plan.tool_dwell_s * 1e12 / static_cast<double>(tick_ps));
  if (!(d < 1e15)) throw InputError("the tool dwell of " + std::to_string(plan.tool_dwell_s) + " s is too long", plan.tape);
  return static_cast<uint64_t>(d);
}

std::vector<uint64_t> tool_ticks(const PlayPlan& plan, uint64_t tick_ps) {
  if (tick_ps == 0) throw InputError("the controller tick is zero");
  const i128 D = static_cast<i128>(plan.scaling.speed.num) * tick_ps;
  const i128 F = static_cast<i128>(plan.header.tick_ps) * plan.scaling.speed.den;
  const i128 dwell = tool_dwell_ticks(plan, tick_ps);
  std::vector<uint64_t> T(plan.tools.size());
  for (size_t j = 0; j < T.size(); ++j)
    T[j] = static_cast<uint64_t>(floor_div(static_cast<i128>(plan.tools[j].t) * F + static_cast<i128>(j) * dwell * D, D));
  return T;
}

namespace {
constexpr int64_t kMaxPlayTicks = int64_t{1} << 47;
}  // namespace

std::vector<StepWindow> step_windows(const PlayPlan& plan, uint64_t tick_ps) {
  if (tick_ps == 0) throw InputError("the controller tick is zero");
  const size_t n = plan.steps.size();
  std::vector<StepWindow> w(n);
  std::vector<i128> X(n);
  // x = t * tape_tick_ps * den / (num * tick_ps) = X / D, plus a tool dwell for every tool item before the step
  const i128 D = static_cast<i128>(plan.scaling.speed.num) * tick_ps;
  const i128 F = static_cast<i128>(plan.header.tick_ps) * plan.scaling.speed.den;
  const i128 dwell = tool_dwell_ticks(plan, tick_ps);
  const std::vector<uint64_t> T = tool_ticks(plan, tick_ps);
  size_t before = 0;  // tool items before step i
  for (size_t i = 0; i < n; ++i) {
    while (before < plan.tools.size() && plan.tools[before].before <= i) ++before;
    X[i] = static_cast<i128>(plan.steps[i].t) * F + static_cast<i128>(before) * dwell * D;
    // the controller's clock and its runs' fixed-point sums are exact up to 2^48 ticks (2^47: a margin of two);
    // checked before the window is narrowed to 64 bits
    if (floor_div(X[i], D) + 1 > kMaxPlayTicks)
      throw InputError("at speed scale " + to_string(plan.scaling.speed) + " the playback would last more than " +
                           significant(static_cast<double>(kMaxPlayTicks) * static_cast<double>(tick_ps) * 1e-12, 3) +
                           " s (2^47 controller ticks of " + significant(static_cast<double>(tick_ps) * 1e-3, 6) +
                           " ns), longer than a controller's clock times: use a larger speed scale",
                       "--speed-scale");
    w[i].lo = static_cast<int64_t>(ceil_div(X[i], D) - 1);
    w[i].hi = static_cast<int64_t>(floor_div(X[i], D) + 1);
    // on its side of the tool items: after the tick of the last one before it, at or before the next one's
    if (before > 0) w[i].lo = std::max(w[i].lo, static_cast<int64_t>(T[before - 1]) + 1);
    if (before < T.size()) w[i].hi = std::min(w[i].hi, static_cast<int64_t>(T[before]));
    if (w[i].lo > w[i].hi)
      throw InputError("machine step " + std::to_string(i + 1) + " (from tape record " +
                       std::to_string(plan.steps[i].record) + ") falls within one controller tick of a tool event at "
                       "speed scale " + to_string(plan.scaling.speed) + ": use a lower speed scale or a finer tick",
                       plan.tape);
  }
  const std::vector<size_t> on_axis[2] = {axis_steps(plan, 0), axis_steps(plan, 1)};
  for (const auto& idx : on_axis) narrow_axis(plan, tick_ps, w, idx);
  // Order across axes: consecutive steps of different axes i, i+1 must execute with tick_i < tick_{i+1}, or equal
  // ticks when i is radial and i+1 angular (the controller steps the radial axis first within a tick). Where the
  // windows would allow a swap, the cluster of such steps gets the ranges that keep the order (a forward and a
  // backward pass of difference constraints), and each pair in it is then split at the tick halfway between
  // their exact times: the earlier step keeps the ticks up to the split, the later one those after it. Any ticks
  // within the split windows keep the tape's order, and every step keeps at least one tick.
  auto delta = [&](size_t i) { return plan.steps[i].axis > plan.steps[i + 1].axis ? 1 : 0; };
  auto conflict = [&](size_t i) {
    return plan.steps[i].axis != plan.steps[i + 1].axis && w[i].hi + delta(i) > w[i + 1].lo;
  };
  size_t i = 0;
  std::vector<int64_t> L, U;
  while (i + 1 < n) {
    if (!conflict(i)) {
      ++i;
      continue;
    }
    size_t e = i + 1;
    while (e + 1 < n && conflict(e)) ++e;
    const size_t m = e - i + 1;
    L.assign(m, 0);
    U.assign(m, 0);
    for (size_t k = 0; k < m; ++k) L[k] = k == 0 ? w[i].lo : std::max(w[i + k].lo, L[k - 1] + delta(i + k - 1));
    for (size_t k = m; k-- > 0;) U[k] = k == m - 1 ? w[e].hi : std::min(w[i + k].hi, U[k + 1] - delta(i + k));
    for (size_t k = 0; k < m; ++k) {
      if (L[k] > U[k]) {
        const PlayStep& s = plan.steps[i + k];
        throw InputError("steps " + std::to_string(i + 1) + " to " + std::to_string(e + 1) +
                         " (from tape record " + std::to_string(s.record) +
                         ") fall so close together that a controller of tick " + significant(tick_ps / 1000.0, 6) +
                         " ns cannot keep their order at speed scale " + to_string(plan.scaling.speed) +
                         ": use a lower speed scale or a controller with a finer tick", plan.tape);
      }
    }
    // split tick s between steps a and a+1: a keeps [from, s], a+1 starts at s + delta; s lies in
    // [max(from, L_{a+1} - delta), min(U_a, U_{a+1} - delta)], which the passes above keep non-empty
    int64_t from = L[0];
    for (size_t k = 0; k + 1 < m; ++k) {
      const size_t a = i + k;
      const int d = delta(a);
      const int64_t half = static_cast<int64_t>(floor_div(X[a] + X[a + 1] + (1 - d) * D, 2 * D));
      const int64_t s = std::clamp(half, std::max(from, L[k + 1] - d), std::min(U[k], U[k + 1] - d));
      w[a].lo = from;
      w[a].hi = s;
      from = s + d;
    }
    w[e].lo = from;
    w[e].hi = U[m - 1];
    i = e + 1;
  }
  for (const auto& idx : on_axis) narrow_axis(plan, tick_ps, w, idx);  // the split may have moved neighbours
  return w;
}

// ------------------------------------------------------------------------------------------- compression

Schedule compress_schedule(const PlayPlan& plan, uint64_t tick_ps, const RunShape& shape) {
  const std::vector<StepWindow> all = step_windows(plan, tick_ps);
  Schedule sc;
  sc.tick_ps = tick_ps;
  AxisItems axes[2];
  for (int axis = 0; axis < 2; ++axis) {
    std::vector<StepWindow> w;
    std::vector<int8_t> dir;
    std::vector<size_t> index;  // plan step index (for messages)
    for (size_t k = 0; k < plan.steps.size(); ++k)
      if (plan.steps[k].axis == axis) {
        w.push_back(all[k]);
        dir.push_back(plan.steps[k].dir);
        index.push_back(k);
      }
    compress_axis(plan, tick_ps, shape, axis, w, dir, index, axes[axis], sc);
  }
  // tool items, each sent before the first item that lets the schedule time reach its tick (the controller stops
  // for want of items at the end of the axis whose queued items end sooner): it is there when its tick comes
  const std::vector<uint64_t> T = tool_ticks(plan, tick_ps);
  sc.tool_dwell_ticks = tool_dwell_ticks(plan, tick_ps);
  size_t tj = 0;
  // sending order: always the axis whose queued schedule ends sooner
  size_t k0 = 0, k1 = 0;
  uint64_t h0 = 0, h1 = 0, done = 0;
  const std::vector<QueueItem>* items[2] = {&axes[0].items, &axes[1].items};
  while (k0 < items[0]->size() || k1 < items[1]->size()) {
    const bool take0 = k1 >= items[1]->size() || (k0 < items[0]->size() && h0 <= h1);
    const int a = take0 ? 0 : 1;
    size_t& k = take0 ? k0 : k1;
    const uint64_t reach = std::min(axes[a].horizon[k], take0 ? h1 : h0);
    for (; tj < T.size() && T[tj] <= reach; ++tj) {
      QueueItem tool;
      tool.kind = ItemKind::tool;
      tool.axis = 0;
      tool.dir = plan.tools[tj].down ? 1 : -1;
      tool.wait = T[tj];
      sc.items.push_back(tool);
      sc.horizon.push_back(std::min(h0, h1));
      sc.steps_before.push_back(done);
      ++sc.tools;
      sc.last_tick = std::max(sc.last_tick, T[tj]);
    }
    sc.items.push_back((*items[a])[k]);
    sc.horizon.push_back(axes[a].horizon[k]);
    sc.steps_before.push_back(done);
    done += axes[a].nsteps[k];
    (take0 ? h0 : h1) = axes[a].horizon[k];
    ++k;
  }
  return sc;
}

std::vector<uint64_t> execute_axis(const std::vector<QueueItem>& items, int axis) {
  std::vector<uint64_t> ticks;
  AxisClock clk;
  for (const QueueItem& it : items) {
    if (it.axis != axis) continue;
    if (it.kind == ItemKind::wait) clk.base += it.wait;
    if (it.kind != ItemKind::run) continue;
    RunCursor cur;
    cur.begin(it);
    while (cur.left > 0) ticks.push_back(clk.advance(cur.next()));
  }
  return ticks;
}

}  // namespace polarcam
