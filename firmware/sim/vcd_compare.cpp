// Compares the step pins of a VCD (recorded by fw_sim) with a tape's steps (`polarcam inspect TAPE --csv`):
// every step present, in order, on its axis and in its direction, and its time within one controller tick of
// the tape's time divided by the speed scale.
//
//   vcd_compare RUN.vcd TAPE.csv SPEED TICK_NS [TOLERANCE_TICKS]
//
// SPEED is K or P/Q (the --speed-scale given to play). Times are measured from the rising edge of the `run`
// signal (the board's LED, raised at schedule tick 0 by the same interrupt and the same code path that raises
// the step pins, so the interrupt's latency is common to both). A step's edge is taken as firing on the tick
// nearest to it; the edges' distance from that tick (the interrupt's jitter) is reported too. Prints a summary;
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

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "vcd_compare: %s\n", what.c_str());
  std::exit(2);
}

struct Edge {
  int64_t t_ps;
  int axis, dir;
};

int64_t unit_ps(const std::string& s) {
  // "1ns", "100 ps", "1us"
  std::string digits, unit;
  for (char c : s) {
    if (c >= '0' && c <= '9') digits += c;
    else if (c != ' ' && c != '\t') unit += c;
  }
  const int64_t n = digits.empty() ? 1 : std::stoll(digits);
  if (unit == "fs") return n / 1000;
  if (unit == "ps") return n;
  if (unit == "ns") return n * 1000;
  if (unit == "us") return n * 1000000;
  if (unit == "ms") return n * 1000000000;
  fail("unknown VCD time unit " + s);
}

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

  // ---- the VCD --------------------------------------------------------------------------------------------
  std::ifstream in(argv[1]);
  if (!in) fail(std::string("cannot read ") + argv[1]);
  std::map<std::string, std::string> id_name;
  int64_t scale = 1000;
  std::string tok, text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream ss(text);
  // header
  while (ss >> tok) {
    if (tok == "$timescale") {
      std::string u, w;
      while (ss >> w && w != "$end") u += w;
      scale = unit_ps(u);
    } else if (tok == "$var") {
      std::string type, size, id, name, w;
      ss >> type >> size >> id >> name;
      while (ss >> w && w != "$end") {
      }
      id_name[id] = name;
    } else if (tok == "$enddefinitions") {
      ss >> tok;  // $end
      break;
    }
  }
  std::map<std::string, int> value;
  int64_t now = 0;
  int64_t run_edge = -1;
  std::vector<Edge> edges;
  while (ss >> tok) {
    if (tok[0] == '#') {
      now = std::stoll(tok.substr(1)) * scale;
      continue;
    }
    if (tok[0] == '$') continue;  // $dumpvars, $end
    int v;
    std::string id;
    if (tok[0] == '0' || tok[0] == '1' || tok[0] == 'x' || tok[0] == 'z') {
      v = tok[0] == '1';
      id = tok.substr(1);
    } else if (tok[0] == 'b') {
      v = tok.find('1') != std::string::npos;
      ss >> id;
    } else {
      continue;
    }
    auto it = id_name.find(id);
    if (it == id_name.end()) continue;
    const std::string& name = it->second;
    const int old = value.count(name) ? value[name] : 0;
    value[name] = v;
    if (v == 1 && old == 0) {
      if (name == "run" && run_edge < 0) run_edge = now;
      if (name == "r_step") edges.push_back({now, 0, value["r_dir"] ? 1 : -1});
      if (name == "theta_step") edges.push_back({now, 1, value["theta_dir"] ? 1 : -1});
    }
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
