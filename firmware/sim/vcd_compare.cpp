// Compares the step pins of a VCD (recorded by fw_sim) with a tape's steps (`polarcam inspect TAPE --csv`):
// every step present, in order, on its axis and in its direction, and its time within one controller tick of
// the tape's time divided by the speed scale.
//
//   vcd_compare RUN.vcd TAPE.csv SPEED TICK_NS [TOLERANCE_TICKS]
//
// SPEED is K or P/Q (the --speed-scale given to play). Times are measured from the rising edge of the `run`
// signal (the board's LED, raised at schedule tick 0 by the same interrupt and the same code path that raises
// the step pins, so the interrupt's latency is common to both). A step's edge is taken as firing on the tick
// nearest to it; the edges' distance from that tick (the interrupt's jitter) is reported too. The VCD is read
// through the encoder capture's VCD reader (capture/vcd.cpp, compiled in by the Makefile). Prints a summary;
// exit status 0 when every step matches within TOLERANCE ticks (default 1), 1 otherwise, 2 for unreadable input.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cam/error.hpp"
#include "capture/vcd.hpp"

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "vcd_compare: %s\n", what.c_str());
  std::exit(2);
}

struct Edge {
  int64_t t_ps;
  int axis, dir;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5 && argc != 6) {
    std::fprintf(stderr, "usage: vcd_compare RUN.vcd TAPE.csv SPEED TICK_NS [TOLERANCE_TICKS]\n");
    return 2;
  }
  // speed scale P/Q
  int64_t P = 1, Q = 1;
  {
    const std::string k = argv[3];
    const size_t slash = k.find('/');
    P = std::atoll(k.substr(0, slash).c_str());
    Q = slash == std::string::npos ? 1 : std::atoll(k.substr(slash + 1).c_str());
    if (P <= 0 || Q <= 0) fail("speed scale " + k + ": give K or P/Q (positive integers)");
  }
  const int64_t tick_ps = std::llround(std::atof(argv[4]) * 1000);
  if (tick_ps <= 0) fail("tick must be positive");
  const double tolerance = argc == 6 ? std::atof(argv[5]) : 1.0;
  if (!(tolerance >= 0)) fail("tolerance must be a number of ticks");

  // ---- the VCD, through the encoder capture's reader (capture/vcd.hpp) ----------------------------------------
  std::ifstream in(argv[1], std::ios::binary);
  if (!in) fail(std::string("cannot read ") + argv[1]);
  enum { kRStep, kRDir, kThetaStep, kThetaDir, kRun };
  int64_t run_edge = -1;
  std::vector<Edge> edges;
  try {
    polarcam::VcdReader vcd(in, argv[1], {"r_step", "r_dir", "theta_step", "theta_dir", "run"});
    polarcam::LevelSample s;
    uint32_t before = 0;  // levels before the sample (unknown counts as 0)
    while (vcd.next(s)) {
      const int64_t now = static_cast<int64_t>(s.t_fs / 1000);  // ps
      auto rose = [&](int bit) {
        const uint32_t m = 1u << bit;
        return (s.changed & m) && (s.levels & m) && !(before & m);
      };
      if (rose(kRun) && run_edge < 0) run_edge = now;
      if (rose(kRStep)) edges.push_back({now, 0, (s.levels >> kRDir) & 1u ? 1 : -1});
      if (rose(kThetaStep)) edges.push_back({now, 1, (s.levels >> kThetaDir) & 1u ? 1 : -1});
      before = s.levels;
    }
  } catch (const polarcam::Error& e) {
    fail(e.what());
  }
  if (run_edge < 0) fail("the VCD has no rising edge of `run` (START)");
  std::stable_sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
    return a.t_ps != b.t_ps ? a.t_ps < b.t_ps : a.axis < b.axis;  // one tick, both axes: radial first
  });

  // ---- the tape (inspect --csv: t_ns,axis,dir,n,m) and the comparison --------------------------------------
  std::ifstream csv(argv[2]);
  if (!csv) fail(std::string("cannot read ") + argv[2]);
  std::string line;
  std::getline(csv, line);  // header
  size_t i = 0, mismatched = 0, tape_steps = 0;
  double max_tick_err = 0, max_raw_err = 0, max_jitter_ns = 0;
  size_t worst = 0;
  const bool list = std::getenv("VCD_COMPARE_LIST") != nullptr;  // the steps off by more than a tick, on stderr
  int listed = 0;
  while (std::getline(csv, line)) {
    if (line.empty()) continue;
    std::istringstream ls(line);
    std::string t, axis, dir;
    std::getline(ls, t, ',');
    std::getline(ls, axis, ',');
    std::getline(ls, dir, ',');
    ++tape_steps;
    if (i >= edges.size()) continue;
    const Edge& e = edges[i++];
    const int a = axis == "r" ? 0 : 1, d = std::atoi(dir.c_str()) > 0 ? 1 : -1;
    if (e.axis != a || e.dir != d) {
      if (mismatched < 5)
        std::fprintf(stderr, "step %zu: the tape has %s %+d, the pins %s %+d\n", i, axis.c_str(), d,
                     e.axis == 0 ? "r" : "theta", e.dir);
      ++mismatched;
      continue;
    }
    // exact controller time of the step: x = t / K, in ps (exact rational, compared in long double)
    const long double x = static_cast<long double>(std::stoll(t)) * 1000.0L * Q / P;
    const int64_t at = e.t_ps - run_edge;
    const int64_t tick = (at + tick_ps / 2) / tick_ps;  // the tick it fired on
    const long double tick_err = std::fabs(static_cast<long double>(tick) * tick_ps - x) / tick_ps;
    const long double raw_err = std::fabs(static_cast<long double>(at) - x) / tick_ps;
    const double jitter = std::fabs(static_cast<double>(at - tick * tick_ps)) / 1000.0;
    if (tick_err > max_tick_err) {
      max_tick_err = static_cast<double>(tick_err);
      worst = i;
    }
    max_raw_err = std::max(max_raw_err, static_cast<double>(raw_err));
    if (list && tick_err > 1.0L && listed++ < 30)
      std::fprintf(stderr, "step %zu %s: at %lld ns, tick %lld, tape %.3Lf ticks, error %.3Lf ticks\n", i,
                   axis.c_str(), static_cast<long long>(at / 1000), static_cast<long long>(tick), x / tick_ps,
                   tick_err);
    max_jitter_ns = std::max(max_jitter_ns, jitter);
  }
  const bool ok = tape_steps == edges.size() && mismatched == 0 && max_tick_err <= tolerance + 1e-9;
  std::printf("steps_tape %zu\nsteps_pins %zu\nmismatched %zu\nmax_error_ticks %.4f\nworst_step %zu\n"
              "max_edge_error_ticks %.4f\nmax_edge_jitter_ns %.1f\ntick_ns %.3f\nspeed_scale %lld/%lld\ntolerance_ticks %g\n"
              "result %s\n",
              tape_steps, edges.size(), mismatched, max_tick_err, worst, max_raw_err, max_jitter_ns,
              static_cast<double>(tick_ps) / 1000.0, static_cast<long long>(P), static_cast<long long>(Q),
              tolerance, ok ? "PASS" : "FAIL");
  return ok ? 0 : 1;
}
