#include "machine/schedule.hpp"

#include <algorithm>
#include <stdexcept>

#include "cam/error.hpp"
#include "machine/int128.hpp"

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

// ------------------------------------------------------------------------------------------- run search

struct Scan {
  uint32_t n = 0;     // steps covered
  i128 imin = 0, imax = 0;
  int dir = 0;        // -1: a smaller add could go further, +1: a larger, 0: stopped by the limit
};

// Steps k = 1..limit of one axis starting from clock C (32.32, absolute): point windows L_k <= k I + T_k A <= U_k
// (relative to C) and every interval in [one tick, kMaxIntervalFx].
struct RunSearch {
  const std::vector<StepWindow>& w;  // this axis's windows
  size_t pos;                        // first step of the run
  uint32_t limit;                    // steps available (same direction, span)
  i128 C;

  i128 L(uint32_t k) const { return (static_cast<i128>(w[pos + k - 1].lo) << kFracBits) - C; }
  i128 U(uint32_t k) const { return ((static_cast<i128>(w[pos + k - 1].hi) + 1) << kFracBits) - 1 - C; }

  Scan scan(i128 A) const {
    Scan s;
    i128 imin = -(static_cast<i128>(1) << 100), imax = static_cast<i128>(1) << 100;
    for (uint32_t k = 1; k <= limit; ++k) {
      const i128 T = static_cast<i128>(k) * (k - 1) / 2;
      i128 a = ceil_div(L(k) - T * A, k), b = floor_div(U(k) - T * A, k);
      a = std::max(a, static_cast<i128>(kOneTick) - static_cast<i128>(k - 1) * A);
      b = std::min(b, static_cast<i128>(kMaxIntervalFx) - static_cast<i128>(k - 1) * A);
      const i128 nmin = std::max(imin, a), nmax = std::min(imax, b);
      if (nmin > nmax) {
        s.dir = b < imin ? -1 : +1;
        return s;
      }
      imin = nmin;
      imax = nmax;
      s.n = k;
      s.imin = imin;
      s.imax = imax;
    }
    s.dir = 0;
    return s;
  }
};

struct Found {
  uint32_t n = 0;
  i128 interval = 0, add = 0;
};

// The value in [lo, hi] (lo <= hi) with the most trailing zero bits, even shifts only, at most 30; the one nearest
// zero among them. The wire format sends deltas shifted right by that many bits, so such values are short.
i128 roundest(i128 lo, i128 hi) {
  if (lo <= 0 && hi >= 0) return 0;
  for (int s = 30; s >= 0; s -= 2) {
    const i128 unit = static_cast<i128>(1) << s;
    const i128 m = lo > 0 ? ceil_div(lo, unit) * unit : floor_div(hi, unit) * unit;
    if (m >= lo && m <= hi) return m;
  }
  return lo;
}

Found best_run(const RunSearch& rs, int64_t prev_interval, int64_t prev_add) {
  Found best;
  Scan one = rs.scan(0);
  if (one.n == 0) return best;
  best.n = 1;
  best.add = prev_add;  // unused by a single step; keeps the add reference unchanged on the wire
  {
    Scan s1 = rs.scan(prev_add);
    if (s1.n >= 1) one = s1;
    else best.add = 0;
  }
  best.interval = prev_interval + roundest(one.imin - prev_interval, one.imax - prev_interval);
  if (rs.limit == 1) return best;
  // the adds allowed by the first two steps
  const i128 i1lo = std::max(rs.L(1), static_cast<i128>(kOneTick)), i1hi = std::min(rs.U(1), static_cast<i128>(kMaxIntervalFx));
  i128 alo = std::max(rs.L(2) - 2 * i1hi, static_cast<i128>(kOneTick) - i1hi);
  i128 ahi = std::min(rs.U(2) - 2 * i1lo, static_cast<i128>(kMaxIntervalFx) - i1lo);
  const i128 alo0 = alo, ahi0 = ahi;
  // bisect on the add for the longest run
  uint32_t bn = 1;
  i128 bA = 0;
  i128 A = std::clamp(static_cast<i128>(prev_add), alo, ahi);
  for (int iter = 0; iter < 100 && alo <= ahi; ++iter) {
    Scan s = rs.scan(A);
    if (s.n > bn) {
      bn = s.n;
      bA = A;
    }
    if (s.dir == 0) break;
    if (s.dir < 0) ahi = A - 1;
    else alo = A + 1;
    if (alo > ahi) break;
    A = alo + (ahi - alo) / 2;
  }
  if (bn < 2) return best;
  // the range of adds that reach bn steps, then the roundest add and interval in it
  i128 lo = alo0, hi = bA;
  while (lo < hi) {
    i128 mid = floor_div(lo + hi, 2);
    if (rs.scan(mid).n >= bn) hi = mid;
    else lo = mid + 1;
  }
  const i128 amin = lo;
  lo = bA;
  hi = ahi0;
  while (lo < hi) {
    i128 mid = ceil_div(lo + hi, 2);
    if (rs.scan(mid).n >= bn) lo = mid;
    else hi = mid - 1;
  }
  const i128 amax = lo;
  i128 chosen = prev_add + roundest(amin - prev_add, amax - prev_add);
  Scan s = rs.scan(chosen);
  if (s.n < bn) {  // the reach is not quite an interval in integers: keep the add the bisection found
    chosen = bA;
    s = rs.scan(chosen);
  }
  best.n = bn;
  best.add = chosen;
  best.interval = prev_interval + roundest(s.imin - prev_interval, s.imax - prev_interval);
  return best;
}

}  // namespace

// ------------------------------------------------------------------------------------------- windows

std::vector<StepWindow> step_windows(const PlayPlan& plan, uint64_t tick_ps) {
  if (tick_ps == 0) throw InputError("the controller tick is zero");
  const size_t n = plan.steps.size();
  std::vector<StepWindow> w(n);
  std::vector<int64_t> target(n);
  // x = t * tape_tick_ps * den / (num * tick_ps) = X / D
  const i128 D = static_cast<i128>(plan.scaling.speed.num) * tick_ps;
  const i128 F = static_cast<i128>(plan.header.tick_ps) * plan.scaling.speed.den;
  for (size_t i = 0; i < n; ++i) {
    const i128 X = static_cast<i128>(plan.steps[i].t) * F;
    const i128 x_floor = floor_div(X, D), x_ceil = ceil_div(X, D);
    w[i].lo = static_cast<int64_t>(x_ceil - 1);
    w[i].hi = static_cast<int64_t>(x_floor + 1);
    target[i] = static_cast<int64_t>(floor_div(2 * X + D, 2 * D));
  }
  // Order across axes: consecutive steps of different axes i, i+1 must execute with tick_i < tick_{i+1}, or equal
  // ticks when i is radial and i+1 angular (the controller steps the radial axis first within a tick). Where the
  // windows would allow a swap, the cluster of such steps is pinned to single ticks chosen nearest the exact
  // times that keep the order.
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
    int64_t prev = 0;
    for (size_t k = 0; k < m; ++k) {
      if (L[k] > U[k]) {
        const PlayStep& s = plan.steps[i + k];
        throw InputError(plan.tape + ": steps " + std::to_string(i + 1) + " to " + std::to_string(e + 1) +
                         " (from tape record " + std::to_string(s.record) +
                         ") fall so close together that a controller of tick " + std::to_string(tick_ps / 1000.0) +
                         " ns cannot keep their order at speed scale " + to_string(plan.scaling.speed) +
                         ": use a lower speed scale or a controller with a finer tick");
      }
      int64_t v = k == 0 ? target[i] : std::max(target[i + k], prev + delta(i + k - 1));
      v = std::clamp(v, L[k], U[k]);
      w[i + k].lo = w[i + k].hi = v;
      prev = v;
    }
    i = e + 1;
  }
  return w;
}

// ------------------------------------------------------------------------------------------- compression

Schedule compress_schedule(const PlayPlan& plan, uint64_t tick_ps) {
  const std::vector<StepWindow> all = step_windows(plan, tick_ps);
  Schedule sc;
  sc.tick_ps = tick_ps;
  // per-axis items
  std::vector<QueueItem> items[2];
  std::vector<uint64_t> horizon[2], nsteps[2];
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
    AxisClock clk;
    int64_t prev_add = 0;
    size_t pos = 0;
    while (pos < w.size()) {
      // long gap: wait until just under the span limit before the window
      if (w[pos].lo > static_cast<int64_t>(clk.base) + kMaxSpanTicks / 2) {
        QueueItem it;
        it.kind = ItemKind::wait;
        it.axis = static_cast<uint8_t>(axis);
        it.wait = static_cast<uint64_t>(w[pos].lo) - clk.base - kMaxSpanTicks / 4;
        clk.base += it.wait;
        items[axis].push_back(it);
        horizon[axis].push_back(clk.base);
        nsteps[axis].push_back(0);
        ++sc.waits;
        continue;
      }
      uint32_t limit = 1;
      while (limit < kMaxRunCount && pos + limit < w.size() && dir[pos + limit] == dir[pos] &&
             w[pos + limit].hi - static_cast<int64_t>(clk.base) < kMaxSpanTicks)
        ++limit;
      RunSearch rs{w, pos, limit, (static_cast<i128>(clk.base) << kFracBits) + clk.frac};
      Found f = best_run(rs, clk.last_interval, prev_add);
      if (f.n == 0) {
        const PlayStep& s = plan.steps[index[pos]];
        throw InputError(plan.tape + ": machine step " + std::to_string(index[pos] + 1) + " (" + axis_name(axis) +
                         ", from tape record " + std::to_string(s.record) +
                         ") comes less than one controller tick after the previous " + axis_name(axis) +
                         " step at speed scale " + to_string(plan.scaling.speed) + " (tick " +
                         std::to_string(tick_ps / 1000.0) + " ns): use a lower speed scale or a finer tick");
      }
      QueueItem it;
      it.kind = ItemKind::run;
      it.axis = static_cast<uint8_t>(axis);
      it.dir = dir[pos];
      it.count = f.n;
      it.interval = static_cast<int64_t>(f.interval);
      it.add = static_cast<int64_t>(f.add);
      // execute exactly as the controller will, and check every step against its window
      int64_t iv = it.interval;
      for (uint32_t k = 0; k < f.n; ++k) {
        if (iv < kOneTick || iv > kMaxIntervalFx) throw std::logic_error("step compression: interval out of range");
        const uint64_t tick = clk.advance(iv);
        if (static_cast<int64_t>(tick) < w[pos + k].lo || static_cast<int64_t>(tick) > w[pos + k].hi)
          throw std::logic_error("step compression: a step left its window");
        if (k + 1 < f.n) iv += it.add;
      }
      clk.last_interval = iv;
      prev_add = it.add;
      items[axis].push_back(it);
      horizon[axis].push_back(clk.base);
      nsteps[axis].push_back(f.n);
      sc.steps[axis] += f.n;
      sc.last_tick = std::max(sc.last_tick, clk.base);
      ++sc.runs;
      pos += f.n;
    }
    QueueItem end;
    end.kind = ItemKind::end;
    end.axis = static_cast<uint8_t>(axis);
    items[axis].push_back(end);
    horizon[axis].push_back(UINT64_MAX);
    nsteps[axis].push_back(0);
  }
  // sending order: always the axis whose queued schedule ends sooner
  size_t k0 = 0, k1 = 0;
  uint64_t h0 = 0, h1 = 0, done = 0;
  while (k0 < items[0].size() || k1 < items[1].size()) {
    const bool take0 = k1 >= items[1].size() || (k0 < items[0].size() && h0 <= h1);
    const int a = take0 ? 0 : 1;
    size_t& k = take0 ? k0 : k1;
    sc.items.push_back(items[a][k]);
    sc.horizon.push_back(horizon[a][k]);
    sc.steps_before.push_back(done);
    done += nsteps[a][k];
    (take0 ? h0 : h1) = horizon[a][k];
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
    int64_t iv = it.interval;
    for (uint32_t k = 0; k < it.count; ++k) {
      ticks.push_back(clk.advance(iv));
      if (k + 1 < it.count) iv += it.add;
    }
  }
  return ticks;
}

// ------------------------------------------------------------------------------------------- wire codec

namespace {
void put_varint(uint64_t v, std::string& out) {
  do {
    uint8_t b = v & 0x7f;
    v >>= 7;
    out.push_back(static_cast<char>(v ? (b | 0x80) : b));
  } while (v);
}
uint64_t zigzag(int64_t v) { return (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63); }
int64_t unzigzag(uint64_t v) { return static_cast<int64_t>(v >> 1) ^ -static_cast<int64_t>(v & 1); }
bool get_varint(const uint8_t* d, size_t len, size_t& pos, uint64_t& v) {
  v = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    if (pos >= len) return false;
    uint8_t b = d[pos++];
    v |= static_cast<uint64_t>(b & 0x7f) << shift;
    if (!(b & 0x80)) return shift < 63 || (b & 0x7e) == 0;
  }
  return false;
}
}  // namespace

void ItemCodec::encode(const QueueItem& it, std::string& out) {
  const int a = it.axis & 1;
  uint8_t tag = static_cast<uint8_t>(a | (static_cast<int>(it.kind) << 1) | (it.dir > 0 ? 8 : 0));
  out.push_back(static_cast<char>(tag));
  if (it.kind == ItemKind::run) {
    const int64_t di = it.interval - last_interval[a], da = it.add - last_add[a];
    auto tz = [](int64_t v) {
      int s = 0;
      while (v != 0 && s < 30 && (v & ((int64_t{1} << (s + 2)) - 1)) == 0) s += 2;
      return s;
    };
    const int si = tz(di), sa = tz(da);
    put_varint(it.count, out);
    out.push_back(static_cast<char>((si / 2) | ((sa / 2) << 4)));
    put_varint(zigzag(di >> si), out);
    put_varint(zigzag(da >> sa), out);
    last_interval[a] = it.interval + static_cast<int64_t>(it.count - 1) * it.add;
    last_add[a] = it.add;
  } else if (it.kind == ItemKind::wait) {
    put_varint(it.wait, out);
  }
}

bool ItemCodec::decode(const uint8_t* d, size_t len, size_t& pos, QueueItem& it) {
  size_t p = pos;
  if (p >= len) return false;
  const uint8_t tag = d[p++];
  if (tag & 0xf0) return false;
  const int kind = (tag >> 1) & 3;
  if (kind > 2) return false;
  QueueItem r;
  r.axis = tag & 1;
  r.kind = static_cast<ItemKind>(kind);
  r.dir = (tag & 8) ? 1 : -1;
  const int a = r.axis;
  if (r.kind == ItemKind::run) {
    uint64_t c, di, da;
    if (!get_varint(d, len, p, c) || p >= len) return false;
    const uint8_t shifts = d[p++];
    const int si = 2 * (shifts & 15), sa = 2 * (shifts >> 4);
    if (si > 30 || sa > 30) return false;
    if (!get_varint(d, len, p, di) || !get_varint(d, len, p, da)) return false;
    if (c == 0 || c > kMaxRunCount) return false;
    const i128 vi = static_cast<i128>(unzigzag(di)) * (int64_t{1} << si), va = static_cast<i128>(unzigzag(da)) * (int64_t{1} << sa);
    const i128 ri = last_interval[a] + vi, ra = last_add[a] + va;
    if (ri < -kMaxIntervalFx || ri > kMaxIntervalFx || ra < -kMaxIntervalFx || ra > kMaxIntervalFx) return false;
    r.count = static_cast<uint32_t>(c);
    r.interval = static_cast<int64_t>(ri);
    r.add = static_cast<int64_t>(ra);
    // every interval of the run must be in range (checked at both ends; it is linear in k)
    const i128 first = r.interval, last = static_cast<i128>(r.interval) + static_cast<i128>(r.count - 1) * r.add;
    if (first < kOneTick || first > kMaxIntervalFx || last < kOneTick || last > kMaxIntervalFx) return false;
    last_interval[a] = static_cast<int64_t>(last);
    last_add[a] = r.add;
  } else if (r.kind == ItemKind::wait) {
    if (!get_varint(d, len, p, r.wait)) return false;
  }
  it = r;
  pos = p;
  return true;
}

}  // namespace polarcam
