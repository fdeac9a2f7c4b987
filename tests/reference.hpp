#pragma once
// A slow, obviously-correct reference digitizer for tests, independent of polarcam's track and root finding:
// it evaluates the tool path through a caller-supplied long-double function, samples it densely, follows the
// same quantiser rule (threshold h: nearest h = 1/2, thesis h = 1) sample by sample, and locates each step by
// bisection on the exact function in long double. Arc length is integrated with adaptive Simpson in long double.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

namespace polarcam::testref {

using LD = long double;

struct P2 {
  LD x, y, dx, dy;  // position and derivative with respect to u
};
using PathFn = std::function<P2(LD u)>;

struct RefStep {
  int axis, dir;
  LD u, t_s;  // parameter and exact time
};

struct RefGrid {
  LD dr, dth;
  LD h = 0.5L;
  LD speed;
  LD theta_shift = 0;  // added to atan2
};

inline LD unwrap(LD a, LD ref) {
  const LD two_pi = 6.283185307179586476925286766559L;
  return a + two_pi * std::nearbyint((ref - a) / two_pi);
}

// Digitizes path(u), u in [u0, u1], sampled at `samples` points. start_node may be given (thesis rule on closed
// paths); otherwise nearest: floor(f + 1/2), thesis: floor(f).
inline std::vector<RefStep> reference_digitize(const PathFn& path, LD u0, LD u1, const RefGrid& g, long samples,
                                               long long* start_node = nullptr, long long* end_node = nullptr,
                                               const long long* given_start = nullptr) {
  auto f_of = [&](LD u, LD ref_th, LD* th_out) {
    P2 p = path(u);
    LD r = std::sqrt(p.x * p.x + p.y * p.y);
    LD th = unwrap(std::atan2(p.y, p.x), ref_th);
    if (th_out) *th_out = th;
    return std::array<LD, 2>{r / g.dr, (th + g.theta_shift) / g.dth};
  };
  LD th0 = std::atan2(path(u0).y, path(u0).x);
  auto f0 = f_of(u0, th0, &th0);
  long long node[2];
  for (int a = 0; a < 2; ++a)
    node[a] = given_start ? given_start[a] : (long long)std::floor(g.h == 0.5L ? f0[a] + 0.5L : f0[a]);
  if (start_node) {
    start_node[0] = node[0];
    start_node[1] = node[1];
  }
  std::vector<RefStep> steps;
  LD prev_u = u0, prev_th = th0;
  std::array<LD, 2> prev_f = f0;
  auto speed = [&](LD u) {
    P2 p = path(u);
    return std::sqrt(p.dx * p.dx + p.dy * p.dy);
  };
  std::function<LD(LD, LD, LD, LD, LD, int)> simpson = [&](LD a, LD b, LD fa, LD fm, LD fb, int depth) -> LD {
    LD m = 0.5L * (a + b), lm = 0.5L * (a + m), rm = 0.5L * (m + b);
    LD flm = speed(lm), frm = speed(rm);
    LD whole = (b - a) / 6 * (fa + 4 * fm + fb);
    LD left = (m - a) / 6 * (fa + 4 * flm + fm), right = (b - m) / 6 * (fm + 4 * frm + fb);
    if (depth > 40 || std::fabs(left + right - whole) <= 1e-22L * (b - a) + 1e-24L) return left + right + (left + right - whole) / 15;
    return simpson(a, m, fa, flm, fm, depth + 1) + simpson(m, b, fm, frm, fb, depth + 1);
  };
  auto arc = [&](LD a, LD b) {
    if (b <= a) return (LD)0;
    return simpson(a, b, speed(a), speed(0.5L * (a + b)), speed(b), 0);
  };
  LD s = 0, s_u = u0;
  for (long i = 1; i <= samples; ++i) {
    LD u = u0 + (u1 - u0) * (LD)i / (LD)samples;
    LD th;
    auto f = f_of(u, prev_th, &th);
    // steps of both axes inside (prev_u, u]; collect then order by u
    std::vector<RefStep> here;
    for (int a = 0; a < 2; ++a) {
      for (;;) {
        LD up = node[a] + g.h, down = node[a] - g.h;
        int dir = 0;
        LD level = 0;
        if (f[a] >= up) {
          dir = 1;
          level = up;
        } else if (f[a] < down) {
          dir = -1;
          level = down;
        }
        if (!dir) break;
        // bisection on the exact function between prev_u and u for this level
        LD lo = prev_u, hi = u;
        for (int it = 0; it < 200 && hi - lo > 0; ++it) {
          LD m = 0.5L * (lo + hi);
          if (m <= lo || m >= hi) break;
          LD tm;
          auto fm = f_of(m, prev_th, &tm);
          bool reached = dir > 0 ? fm[a] >= level : fm[a] < level;
          (reached ? hi : lo) = m;
        }
        here.push_back({a, dir, hi, 0});
        node[a] += dir;
      }
    }
    std::sort(here.begin(), here.end(), [](const RefStep& x, const RefStep& y) {
      return x.u < y.u || (x.u == y.u && x.axis < y.axis);
    });
    for (auto& st : here) {
      s += arc(s_u, st.u);
      s_u = st.u;
      st.t_s = s / g.speed;
      steps.push_back(st);
    }
    prev_u = u;
    prev_th = th;
    prev_f = f;
  }
  if (end_node) {
    end_node[0] = node[0];
    end_node[1] = node[1];
  }
  return steps;
}

}  // namespace polarcam::testref
