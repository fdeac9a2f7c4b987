#pragma once
// The test side of the encoder capture: a step sequence (a tape's steps) written as the quadrature edges two
// encoders would give, as a VCD or a CSV, with no capture code. An axis's count n sets its channels (A, B) to
// 00, 10, 11, 01 for n mod 4 = 0, 1, 2, 3 (A leads B when counting up); with c counts per step the count stands
// at c k on node k when it arrived from below, and a step down from there is the single edge to c k - 1 (the
// step index is floor(count / c)). The last edge of a step falls at the step's time; the edges before it are
// spaced `lead_ns` apart before it. Jitter moves every edge by a uniform amount in [-jitter, +jitter] ns and
// then the analyser quantises it to its sample period.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace polarcam::test {

struct QStep {
  int64_t t_ns;
  int axis, dir;
};

struct QEdge {
  int64_t t;     // in the file's time unit
  int channel;   // 0 r_a, 1 r_b, 2 theta_a, 3 theta_b
  int level;
};

struct QuadratureWriterOptions {
  int64_t counts_per_step = 1;
  int64_t lead_ns = 1000;    // spacing of a step's earlier edges
  int64_t unit_ns = 1;       // the analyser's sample period (the file's time unit)
  int64_t jitter_ns = 0;
  uint32_t seed = 1;
  int64_t start_ns = 0;      // the time of the first (initial-level) sample
  int64_t tail_ns = 0;       // the file's last time after the last step
};

// The edges, in time order (ties: in the order generated), and the initial levels of the four channels.
inline std::vector<QEdge> quadrature_edges(const std::vector<QStep>& steps, const QuadratureWriterOptions& o,
                                           int initial[4], int64_t& end_unit) {
  static constexpr int kA[4] = {0, 1, 1, 0}, kB[4] = {0, 0, 1, 1};
  const int64_t c = o.counts_per_step;
  int64_t count[2] = {0, 0}, node[2] = {0, 0};
  for (int ch = 0; ch < 4; ++ch) initial[ch] = 0;
  std::mt19937 rng(o.seed);
  std::uniform_int_distribution<int64_t> jit(-o.jitter_ns, o.jitter_ns);
  auto level = [&](int64_t n, int which) {
    const int64_t m = ((n % 4) + 4) % 4;
    return which == 0 ? kA[m] : kB[m];
  };
  struct Raw {
    int64_t t_ns;
    size_t order;
    int channel, level;
  };
  std::vector<Raw> raw;
  int64_t last_t = 0;
  for (const QStep& s : steps) {
    const int64_t target = s.dir > 0 ? c * (node[s.axis] + 1) : c * node[s.axis] - 1;
    const int64_t edges = target > count[s.axis] ? target - count[s.axis] : count[s.axis] - target;
    const int d = target > count[s.axis] ? 1 : -1;
    for (int64_t e = 0; e < edges; ++e) {
      const int64_t before = count[s.axis];
      count[s.axis] += d;
      const int64_t t = s.t_ns - (edges - 1 - e) * o.lead_ns;
      // the channel that changes between two neighbouring counts
      const int which = level(before, 0) != level(count[s.axis], 0) ? 0 : 1;
      raw.push_back({t + o.start_ns, raw.size(), 2 * s.axis + which, level(count[s.axis], which)});
    }
    node[s.axis] += s.dir;
    last_t = std::max(last_t, s.t_ns);
  }
  std::vector<QEdge> out;
  out.reserve(raw.size());
  for (Raw& r : raw) {
    int64_t t = r.t_ns + (o.jitter_ns ? jit(rng) : 0);
    t = std::max<int64_t>(t, o.start_ns + o.unit_ns);  // after the initial levels
    const int64_t q = (t + o.unit_ns / 2) / o.unit_ns;  // the sample that sees it
    out.push_back({q, r.channel, r.level});
  }
  std::stable_sort(out.begin(), out.end(), [](const QEdge& a, const QEdge& b) { return a.t < b.t; });
  end_unit = (o.start_ns + last_t + o.tail_ns + o.unit_ns / 2) / o.unit_ns;
  if (!out.empty()) end_unit = std::max(end_unit, out.back().t);
  return out;
}

// A VCD with `timescale` (e.g. "1 ns", matching unit_ns), the four channels under scopes top.enc, and an extra
// signal `noise` toggling beside them that the capture must ignore.
inline std::string quadrature_vcd(const std::vector<QStep>& steps, const QuadratureWriterOptions& o,
                                  const std::string& timescale) {
  int init[4];
  int64_t end = 0;
  const std::vector<QEdge> edges = quadrature_edges(steps, o, init, end);
  static const char* kId[4] = {"!", "\"", "#", "$"};
  std::string s = "$date today $end\n$version quadrature writer $end\n$timescale " + timescale +
                  " $end\n$scope module top $end\n$scope module enc $end\n"
                  "$var wire 1 ! r_a $end\n$var wire 1 \" r_b $end\n$var wire 1 # theta_a $end\n"
                  "$var wire 1 $ theta_b $end\n$upscope $end\n$var wire 1 % noise $end\n$upscope $end\n"
                  "$enddefinitions $end\n";
  const int64_t start = o.start_ns / o.unit_ns;
  s += '#';
  s += std::to_string(start);
  s += "\n$dumpvars\n";
  for (int ch = 0; ch < 4; ++ch) {
    s += static_cast<char>('0' + init[ch]);
    s += kId[ch];
    s += '\n';
  }
  s += "0%\n$end\n";
  int64_t now = start;
  int noise = 0;
  for (const QEdge& e : edges) {
    if (e.t != now) {
      now = e.t;
      s += '#';
      s += std::to_string(now);
      s += '\n';
      noise ^= 1;
      s += noise ? "1%\n" : "0%\n";
    }
    s += static_cast<char>('0' + e.level);
    s += kId[e.channel];
    s += '\n';
  }
  if (end > now) {
    s += '#';
    s += std::to_string(end);
    s += '\n';
  }
  return s;
}

// A CSV: time_s with the sample period's decimals, a column `noise` first, then the four channels in the order
// theta_b, r_a, theta_a, r_b (the reader finds them by name); one row per time at which a channel changes.
inline std::string quadrature_csv(const std::vector<QStep>& steps, const QuadratureWriterOptions& o, int decimals) {
  int init[4];
  int64_t end = 0;
  const std::vector<QEdge> edges = quadrature_edges(steps, o, init, end);
  int lv[4] = {init[0], init[1], init[2], init[3]};
  std::string s = "; written by the test's quadrature writer\nnoise,time_s,theta_b,r_a,theta_a,r_b\n";
  auto row = [&](int64_t t_unit) {
    // t_unit * unit_ns ns as seconds with `decimals` decimals (exact: unit_ns is a power of ten >= 10^(9-decimals))
    const int64_t ns = t_unit * o.unit_ns;
    char buf[96];
    int64_t scale = 1;
    for (int i = 0; i < 9 - decimals; ++i) scale *= 10;
    const int64_t v = ns / scale;
    int64_t p = 1;
    for (int i = 0; i < decimals; ++i) p *= 10;
    std::snprintf(buf, sizeof buf, "7,%lld.%0*lld,%d,%d,%d,%d\n", static_cast<long long>(v / p), decimals,
                  static_cast<long long>(v % p), lv[3], lv[0], lv[2], lv[1]);
    s += buf;
  };
  const int64_t start = o.start_ns / o.unit_ns;
  row(start);
  for (size_t i = 0; i < edges.size(); ++i) {
    lv[edges[i].channel] = edges[i].level;
    if (i + 1 == edges.size() || edges[i + 1].t != edges[i].t) row(edges[i].t);
  }
  if (end > (edges.empty() ? start : edges.back().t)) row(end);
  return s;
}

}  // namespace polarcam::test
