#include "machine/cartesian/dda.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "cam/arc_fit.hpp"  // segment_length
#include "cam/error.hpp"
#include "cam/format.hpp"

namespace polarcam {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = 0.5 * std::numbers::pi;
constexpr int kSign[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};  // signs of (x, y) in each quadrant
constexpr int64_t kUnit[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};  // direction of the axis at k pi/2

std::string num(double v, int prec = 6) { return significant(v, prec); }

class Builder {
 public:
  explicit Builder(DdaProgram& p) : p_(p) {}

  // Feed word for `cycles_per_s` DDA cycles per second.
  uint32_t feed_word(double cycles_per_s) const {
    const double f = p_.options.interrupt_hz, cap = p_.options.feed_capacity;
    const double F = std::nearbyint(cap * cycles_per_s / f);
    if (F > cap)
      throw InputError("the speed " + num(p_.speed * 1e3) + " mm/s needs " + num(cycles_per_s, 5) +
                       " DDA cycles per second at a resolution of " + num(p_.blu * 1e3) + " mm, more than the " +
                       num(f) + " Hz interrupt rate gives (one cycle per interrupt at most): raise the interrupt rate "
                       "to at least " + num(std::ceil(cycles_per_s)) + " Hz, lower the speed or coarsen the resolution");
    if (!(F >= 1.0))
      throw InputError("the feed word rounds to zero: " + num(cycles_per_s, 5) + " DDA cycles per second are less than " +
                       "one " + num(cap) + "th of the " + num(f) + " Hz interrupt rate; lower the interrupt rate");
    return static_cast<uint32_t>(F);
  }

  void line(const int64_t a[2], const int64_t b[2]) {
    const int64_t dx = b[0] - a[0], dy = b[1] - a[1];
    if (dx == 0 && dy == 0) return;
    DdaBlock k;
    k.kind = DdaBlock::Kind::line;
    set_ends(k, a, b);
    k.length_blu = std::hypot(static_cast<double>(dx), static_cast<double>(dy));
    k.path = std::llround(k.length_blu);  // >= max(|dx|, |dy|) >= 1
    k.feed = feed_word(p_.speed / p_.blu * static_cast<double>(k.path) / k.length_blu);
    push(k);
  }

  void arc(const int64_t a[2], const int64_t b[2], const PathSegment& seg) {
    if (a[0] == b[0] && a[1] == b[1]) return;
    const int64_t c[2] = {cartesian_node(seg.center.x, p_.blu), cartesian_node(seg.center.y, p_.blu)};
    const double rax = static_cast<double>(a[0] - c[0]), ray = static_cast<double>(a[1] - c[1]);
    const double rbx = static_cast<double>(b[0] - c[0]), rby = static_cast<double>(b[1] - c[1]);
    const double R = std::hypot(rax, ray);
    if (R < 2.0 || std::hypot(rbx, rby) < 2.0) return line(a, b);
    const double a0 = std::atan2(ray, rax), a1 = std::atan2(rby, rbx);
    // the rounded sweep: a1 - a0 plus the whole turns that bring it closest to the fitted sweep
    double sweep = a1 - a0;
    sweep += 2.0 * kPi * std::nearbyint((seg.sweep - sweep) / (2.0 * kPi));
    if (!(sweep * seg.sweep > 0.0) || std::abs(sweep) < 1e-12) return line(a, b);
    const bool ccw = sweep > 0;
    const int64_t Rn = std::llround(R);
    // split at the axes crossed strictly inside the sweep
    std::vector<double> angles{a0};
    std::vector<std::array<int64_t, 2>> nodes{{a[0], a[1]}};
    constexpr double eps = 1e-12;
    const double a_end = a0 + sweep;
    double k = ccw ? std::floor(a0 / kHalfPi + eps) + 1.0 : std::ceil(a0 / kHalfPi - eps) - 1.0;
    for (int guard = 0; guard < 16; ++guard, k += ccw ? 1.0 : -1.0) {
      const double ang = k * kHalfPi;
      if (ccw ? !(ang < a_end - eps) : !(ang > a_end + eps)) break;
      const int q = static_cast<int>(((static_cast<int64_t>(k) % 4) + 4) % 4);
      angles.push_back(ang);
      nodes.push_back({c[0] + Rn * kUnit[q][0], c[1] + Rn * kUnit[q][1]});
    }
    angles.push_back(a_end);
    nodes.push_back({b[0], b[1]});
    for (size_t i = 0; i + 1 < nodes.size(); ++i)
      quadrant_block(nodes[i].data(), nodes[i + 1].data(), c, R, angles[i], angles[i + 1], ccw);
  }

 private:
  static void set_ends(DdaBlock& k, const int64_t a[2], const int64_t b[2]) {
    for (int i = 0; i < 2; ++i) {
      k.from[i] = a[i];
      k.to[i] = b[i];
    }
  }

  void push(const DdaBlock& k) {
    p_.blocks.push_back(k);
    (k.kind == DdaBlock::Kind::line ? p_.line_blocks : p_.arc_blocks) += 1;
    p_.length_m += k.length_blu * p_.blu;
  }

  void quadrant_block(const int64_t* a, const int64_t* b, const int64_t* c, double R, double ang0, double ang1,
                      bool ccw) {
    if (a[0] == b[0] && a[1] == b[1]) return;
    const double mid = 0.5 * (ang0 + ang1);
    const int q = static_cast<int>(((static_cast<int64_t>(std::floor(mid / kHalfPi)) % 4) + 4) % 4);
    const int64_t m0[2] = {kSign[q][0] * (a[0] - c[0]), kSign[q][1] * (a[1] - c[1])};  // |x|, |y| at the start
    const int64_t m1[2] = {kSign[q][0] * (b[0] - c[0]), kSign[q][1] * (b[1] - c[1])};  // and at the end
    // axis a grows in magnitude: y in quadrants 0 and 2 counter-clockwise (x in 1 and 3), the reverse clockwise
    const int ia = ((q % 2 == 0) == ccw) ? 1 : 0, ib = 1 - ia;
    if (m0[0] < 0 || m0[1] < 0 || m1[0] < 0 || m1[1] < 0 || m1[ia] < m0[ia] || m1[ib] > m0[ib]) {
      ++p_.arcs_as_lines;  // the rounded ends do not move the way the quadrant's arc does
      return line(a, b);
    }
    DdaBlock k;
    k.kind = DdaBlock::Kind::arc;
    set_ends(k, a, b);
    k.center[0] = c[0];
    k.center[1] = c[1];
    k.quadrant = q;
    k.ccw = ccw;
    k.length_blu = R * std::abs(ang1 - ang0);
    // the integrands never exceed |b| at the start (a-register) and |a| at the end (b-register)
    k.path = std::max<int64_t>({std::llround(R), m0[ib], m1[ia], 1});
    k.feed = feed_word(p_.speed / p_.blu * static_cast<double>(k.path) / R);
    push(k);
  }

  DdaProgram& p_;
};

// Time of interrupt J, ns.
int64_t interrupt_ns(uint64_t J, double hz) {
  return static_cast<int64_t>(std::llround(static_cast<long double>(J) * (1e9L / static_cast<long double>(hz))));
}

}  // namespace

DdaProgram make_dda_program(const std::vector<PathSegment>& segs, bool closed, double blu, double speed,
                            const DdaOptions& opt) {
  if (!(blu > 0.0) || !std::isfinite(blu)) throw InputError("the Cartesian resolution must be a positive length");
  if (!(speed > 0.0) || !std::isfinite(speed)) throw InputError("the speed must be positive");
  if (!(opt.interrupt_hz > 0.0) || !std::isfinite(opt.interrupt_hz) || opt.interrupt_hz > 1e9)
    throw InputError("the interrupt rate must be a positive frequency up to 1 GHz");
  if (opt.feed_capacity < 2) throw InputError("the feed accumulator's capacity must be at least 2");
  if (segs.empty()) throw InputError("the path has no lines or arcs");
  DdaProgram p;
  p.blu = blu;
  p.speed = speed;
  p.options = opt;
  p.closed = closed;
  p.start[0] = cartesian_node(segs.front().from.x, blu);
  p.start[1] = cartesian_node(segs.front().from.y, blu);
  double length = 0.0;
  for (const PathSegment& s : segs) length += segment_length(s);
  check_step_budget(length, blu);
  Builder b(p);
  int64_t cur[2] = {p.start[0], p.start[1]};
  for (size_t i = 0; i < segs.size(); ++i) {
    const PathSegment& s = segs[i];
    int64_t to[2];
    if (closed && i + 1 == segs.size()) {
      to[0] = p.start[0];
      to[1] = p.start[1];
    } else {
      to[0] = cartesian_node(s.to.x, blu);
      to[1] = cartesian_node(s.to.y, blu);
    }
    if (s.kind == PathSegment::Kind::line)
      b.line(cur, to);
    else
      b.arc(cur, to, s);
    cur[0] = to[0];
    cur[1] = to[1];
  }
  return p;
}

CartesianResult run_dda(const DdaProgram& p, StepSink* sink, DdaStats* stats) {
  CartesianResult res;
  res.closed = p.closed;
  res.path_length_m = p.length_m;
  CartesianTally tally(res, sink);
  tally.start_at(p.start);
  const uint64_t cap = p.options.feed_capacity;
  const double hz = p.options.interrupt_hz;
  uint64_t J0 = 0;  // interrupt at which the previous block ended
  DdaStats st;
  for (const DdaBlock& k : p.blocks) {
    if (tally.node()[0] != k.from[0] || tally.node()[1] != k.from[1])
      throw std::logic_error("internal error: a DDA block does not start where the previous one ended");
    const uint64_t F = k.feed;
    const int64_t Q = k.path;
    uint64_t cycle = 0, J = J0;
    auto next_cycle = [&] {
      ++cycle;
      J = J0 + (cycle * cap + F - 1) / F;  // the feed accumulator (cleared at the block) overflows for the cycle-th time
      return interrupt_ns(J, hz);
    };
    if (k.kind == DdaBlock::Kind::line) {
      const int64_t d[2] = {k.to[0] - k.from[0], k.to[1] - k.from[1]};
      const int64_t inc[2] = {d[0] < 0 ? -d[0] : d[0], d[1] < 0 ? -d[1] : d[1]};
      const int dir[2] = {d[0] < 0 ? -1 : 1, d[1] < 0 ? -1 : 1};
      int64_t cnt[2] = {inc[0], inc[1]}, reg[2] = {0, 0};
      while (cnt[0] > 0 || cnt[1] > 0) {
        const int64_t t = next_cycle();
        for (int ax = 0; ax < 2; ++ax) {
          if (cnt[ax] == 0) continue;
          reg[ax] += inc[ax];
          if (reg[ax] >= Q) {
            reg[ax] -= Q;
            --cnt[ax];
            tally.step(ax, dir[ax], t);
          }
        }
        if (cycle > static_cast<uint64_t>(Q)) throw std::logic_error("internal error: a linear DDA block overran");
      }
    } else {
      const int q = k.quadrant;
      const int ia = ((q % 2 == 0) == k.ccw) ? 1 : 0, ib = 1 - ia;
      const int64_t mag0[2] = {kSign[q][0] * (k.from[0] - k.center[0]), kSign[q][1] * (k.from[1] - k.center[1])};
      const int64_t mag1[2] = {kSign[q][0] * (k.to[0] - k.center[0]), kSign[q][1] * (k.to[1] - k.center[1])};
      int64_t Ia = mag0[ia], Ib = mag0[ib];              // |a| and |b|: the integrands
      int64_t ca = mag1[ia] - mag0[ia], cb = mag0[ib] - mag1[ib];  // axis counters
      const int da = kSign[q][ia], db = -kSign[q][ib];   // |a| grows, |b| shrinks
      int64_t Ra = 0, Rb = 0;
      const uint64_t limit = static_cast<uint64_t>(Q + 1) * static_cast<uint64_t>(ca + cb + 2);
      while (ca > 0 || cb > 0) {
        const int64_t t = next_cycle();
        // Each register integrates as in the listing. Once the other axis has run out its count, an axis that
        // still owes steps takes one every cycle (end-point clean-up); steps its register would not have made
        // that cycle are counted.
        if (ca > 0) {
          const bool overflow = (Ra += Ib) >= Q;
          if (overflow) Ra -= Q;
          if (overflow || cb == 0) {
            if (!overflow) ++st.cleanup_steps;
            --ca;
            ++Ia;
            tally.step(ia, da, t);
          }
        }
        if (cb > 0) {
          const bool overflow = (Rb += Ia) >= Q;
          if (overflow) Rb -= Q;
          if (overflow || ca == 0) {
            if (!overflow) ++st.cleanup_steps;
            --cb;
            --Ib;
            tally.step(ib, db, t);
          }
        }
        if (cycle > limit) throw std::logic_error("internal error: a circular DDA block overran");
      }
    }
    st.cycles += cycle;
    J0 = J;
    if (tally.node()[0] != k.to[0] || tally.node()[1] != k.to[1])
      throw std::logic_error("internal error: a DDA block did not end on its end point");
  }
  st.interrupts = J0;
  res.duration_ns = interrupt_ns(J0, hz);
  res.duration_s = static_cast<double>(J0) / hz;
  tally.finish();
  if (p.closed && !res.returns_to_start)
    throw std::logic_error("internal error: a closed DDA program did not return to its start node");
  if (stats) *stats = st;
  return res;
}

}  // namespace polarcam
