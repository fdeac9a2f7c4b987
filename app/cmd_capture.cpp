// polarcam capture FILE --machine M [-o OUT.tape] [--signals ...] [--format vcd|csv] [--start R,THETA]
//                  [--window N] [--speed-tolerance F] [--json]
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "cam/format.hpp"
#include "capture/capture.hpp"
#include "io/output.hpp"

#ifndef POLARCAM_VERSION
#define POLARCAM_VERSION "0.0.0"
#endif

namespace polarcam::cli {
namespace {

const char* kAxis[2] = {"radial", "angular"};

std::string levels(int ab) { return std::string(1, static_cast<char>('0' + (ab >> 1))) + static_cast<char>('0' + (ab & 1)); }

double seconds(int64_t ns) { return static_cast<double>(ns) * 1e-9; }

std::string num(double v, int digits = 6) { return polarcam::significant(v, digits); }

nlohmann::ordered_json summary_json(const CaptureResult& r, const CaptureOptions& o, const std::string& out) {
  nlohmann::ordered_json j;
  j["format"] = to_string(r.format);
  j["signals"] = {{"r_a", r.matched.at(0)}, {"r_b", r.matched.at(1)}, {"theta_a", r.matched.at(2)},
                  {"theta_b", r.matched.at(3)}};
  j["resolution_s"] = static_cast<double>(r.resolution_fs) * 1e-15;
  j["tick_s"] = 1e-9;
  j["origin_s"] = static_cast<double>(r.origin_fs) * 1e-15;
  j["duration_s"] = seconds(r.duration_ns);
  j["samples"] = r.samples;
  j["counts_per_step"] = o.counts_per_step;
  nlohmann::ordered_json counts;
  for (int a = 0; a < 2; ++a)
    counts[kAxis[a]] = {{"plus", r.counts_plus[a]},
                        {"minus", r.counts_minus[a]},
                        {"net", static_cast<int64_t>(r.counts_plus[a]) - static_cast<int64_t>(r.counts_minus[a])}};
  j["counts"] = counts;
  nlohmann::ordered_json il;
  il["total"] = r.illegal_total;
  il["radial"] = r.illegal_axis[0];
  il["angular"] = r.illegal_axis[1];
  il["listed"] = r.illegal.size();
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const IllegalTransition& t : r.illegal)
    list.push_back({{"t_s", seconds(t.t_ns)}, {"line", t.line}, {"axis", kAxis[t.axis]}, {"from", levels(t.from)},
                    {"to", levels(t.to)}});
  il["list"] = list;
  j["illegal_transitions"] = il;
  j["steps_total"] = r.steps_plus[0] + r.steps_minus[0] + r.steps_plus[1] + r.steps_minus[1];
  j["steps_radial_plus"] = r.steps_plus[0];
  j["steps_radial_minus"] = r.steps_minus[0];
  j["steps_angular_plus"] = r.steps_plus[1];
  j["steps_angular_minus"] = r.steps_minus[1];
  j["start_node"] = {r.start[0], r.start[1]};
  j["end_node"] = {r.end[0], r.end[1]};
  j["last_step_s"] = seconds(r.last_step_ns);
  j["path_length_m"] = r.path_length_m;
  const CaptureSpeed& s = r.speed;
  nlohmann::ordered_json sp;
  sp["window_steps"] = s.window_steps;
  sp["windows"] = s.windows;
  sp["mean_mps"] = s.mean_mps;
  sp["median_mps"] = s.median_mps;
  sp["min_mps"] = s.min_mps;
  sp["min_at_s"] = seconds(s.min_at_ns);
  sp["max_mps"] = s.max_mps;
  sp["max_at_s"] = seconds(s.max_at_ns);
  sp["tolerance"] = s.tolerance;
  sp["steady_fraction"] = s.steady_fraction;
  sp["varied_windows"] = s.varied_windows;
  sp["varied_stretches"] = s.varied_stretches;
  nlohmann::ordered_json varied = nlohmann::ordered_json::array();
  for (const SpeedStretch& v : s.varied)
    varied.push_back({{"from_s", seconds(v.from_ns)}, {"to_s", seconds(v.to_ns)}, {"min_mps", v.min_mps},
                      {"max_mps", v.max_mps}, {"windows", v.windows}});
  sp["varied"] = varied;
  j["speed"] = sp;
  if (!out.empty()) j["tape"] = out;
  return j;
}

std::string summary_text(const std::string& file, const CaptureResult& r, const std::string& out) {
  std::ostringstream os;
  os << "polarcam capture " << file << " (" << to_string(r.format) << ", resolution "
     << num(static_cast<double>(r.resolution_fs) * 1e-15) << " s)\n";
  for (int a = 0; a < 2; ++a)
    os << "  " << (a ? "angular" : "radial ") << "    counts +" << thousands(r.counts_plus[a]) << " / -"
       << thousands(r.counts_minus[a]) << ", steps +" << thousands(r.steps_plus[a]) << " / -"
       << thousands(r.steps_minus[a]) << ", illegal transitions " << thousands(r.illegal_axis[a]) << "\n";
  for (size_t i = 0; i < r.illegal.size() && i < 10; ++i) {
    const IllegalTransition& t = r.illegal[i];
    os << "  illegal    " << kAxis[t.axis] << " " << levels(t.from) << " -> " << levels(t.to) << " at "
       << num(seconds(t.t_ns), 10) << " s (line " << t.line << ")\n";
  }
  if (r.illegal_total > 10) os << "  illegal    ... " << thousands(r.illegal_total - 10) << " more (--json lists them)\n";
  os << "  time       " << num(seconds(r.duration_ns)) << " s, path " << num(r.path_length_m * 1e3)
     << " mm\n";
  const CaptureSpeed& s = r.speed;
  if (s.windows) {
    os << "  speed      mean " << num(s.mean_mps * 1e3, 5) << " mm/s, median "
       << num(s.median_mps * 1e3, 5) << " mm/s, min " << num(s.min_mps * 1e3, 5) << " mm/s at "
       << num(seconds(s.min_at_ns)) << " s, max " << num(s.max_mps * 1e3, 5) << " mm/s at "
       << num(seconds(s.max_at_ns)) << " s (" << thousands(s.windows) << " windows of " << s.window_steps
       << " steps)\n";
    os << "  steady     " << num(100.0 * s.steady_fraction, 4) << " % of the time within "
       << num(100.0 * s.tolerance, 3) << " % of the median; " << thousands(s.varied_stretches)
       << " stretches varied\n";
    for (size_t i = 0; i < s.varied.size() && i < 10; ++i)
      os << "  varied     " << num(seconds(s.varied[i].from_ns)) << " .. "
         << num(seconds(s.varied[i].to_ns)) << " s: " << num(s.varied[i].min_mps * 1e3, 5) << " .. "
         << num(s.varied[i].max_mps * 1e3, 5) << " mm/s\n";
  } else {
    os << "  speed      fewer steps than one window (" << s.window_steps << "): not measured\n";
  }
  os << "  nodes      start [" << r.start[0] << ", " << r.start[1] << "], end [" << r.end[0] << ", " << r.end[1]
     << "]\n";
  if (!out.empty()) {
    os << "  tape       " << out;
    if (const auto size = regular_file_size(out)) os << " (" << thousands(*size) << " bytes)";
    os << "\n";
  }
  return os.str();
}

// "R,THETA" with units: the node nearest to it.
void start_node(const std::string& text, const Grid& g, int64_t node[2]) {
  const size_t comma = text.find(',');
  if (comma == std::string::npos || text.find(',', comma + 1) != std::string::npos)
    throw InputError("give the start as R,THETA with units (e.g. \"76.2 mm,0 rad\")", "--start");
  const double r = option_quantity(text.substr(0, comma), dim::length, "--start");
  const double th = option_quantity(text.substr(comma + 1), dim::angle, "--start");
  const double n = std::round(r / g.dr), m = std::round(th / g.dtheta);
  if (!(std::abs(n) <= kMaxNodeIndex) || !(std::abs(m) <= kMaxNodeIndex))
    throw InputError("lies beyond 2^50 steps of the machine's grid from the pole", "--start");
  node[0] = static_cast<int64_t>(n);
  node[1] = static_cast<int64_t>(m);
}

}  // namespace

void register_capture(CLI::App& app, Action& action) {
  struct Opts {
    std::string file, out, machine, signals, format, start;
    int window = 100;
    double tolerance = 0.05;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "capture", "Decode two quadrature encoders recorded by a logic analyser (VCD or CSV) into a step tape");
  c->add_option("file", o->file, "the recording: a VCD file, or a CSV of time_s and the four levels")->required();
  c->add_option("--machine", o->machine, "machine file (grid, home, counts_per_step)")->required();
  c->add_option("-o,--output", o->out, "write the step tape to this file");
  c->add_option("--signals", o->signals,
                "the channels' names in the file, e.g. r_a=D0,r_b=D1,theta_a=D2,theta_b=D3 (default r_a r_b "
                "theta_a theta_b)");
  c->add_option("--format", o->format, "vcd or csv (default: from the file name, else the content)");
  c->add_option("--start", o->start, "the node before the first step, as R,THETA (default: the machine's home)");
  c->add_option("--window", o->window, "steps per speed window (default 100)");
  c->add_option("--speed-tolerance", o->tolerance,
                "a window varies when off the median speed by more than this fraction (default 0.05)");
  c->add_flag("--json", o->json, "print the counts, illegal transitions and speed statistics as one JSON object");
  c->callback([o, &action] {
    action = [o] {
      CaptureOptions co;
      if (!o->signals.empty()) co.signals = parse_capture_signals(o->signals);
      if (o->window < 1) throw InputError("must be a whole number of steps from 1", "--window");
      co.window_steps = o->window;
      if (!(o->tolerance > 0) || !std::isfinite(o->tolerance))
        throw InputError("must be a positive fraction (0.05 is 5 %)", "--speed-tolerance");
      co.speed_tolerance = o->tolerance;
      if (!o->format.empty() && o->format != "vcd" && o->format != "csv")
        throw InputError("'" + o->format + "' is not a capture format: give vcd or csv", "--format");
      nlohmann::ordered_json prov;
      const Machine m = load_machine(o->machine, &prov);
      co.grid = m.grid;
      co.coupling = m.coupling;
      co.counts_per_step = m.counts_per_step;
      co.start[0] = m.grid.home_n();
      co.start[1] = m.grid.home_m();
      if (!o->start.empty()) start_node(o->start, m.grid, co.start);
      if (!o->out.empty()) check_output_path(o->out);
      CaptureFormat format;
      {
        std::ifstream in(o->file, std::ios::binary);
        if (!in) throw InputError("cannot be read: give a VCD or CSV file of the encoder levels", o->file);
        format = capture_format(o->format, o->file, in);
      }
      const CaptureResult r =
          capture_to_tape(o->file, format, co, o->out, prov, std::string("polarcam ") + POLARCAM_VERSION);
      if (r.illegal_total)  // reported, never dropped silently: on the terminal even with --json
        std::fprintf(stderr,
                     "warning: %llu illegal transitions (both channels of an encoder changed at once; their counts "
                     "are lost), the first on the %s encoder at %s s (%s:%llu)\n",
                     static_cast<unsigned long long>(r.illegal_total), kAxis[r.illegal.front().axis],
                     num(seconds(r.illegal.front().t_ns), 10).c_str(), o->file.c_str(),
                     static_cast<unsigned long long>(r.illegal.front().line));
      if (o->json)
        std::cout << summary_json(r, co, o->out).dump(2) << "\n";
      else
        std::cout << summary_text(o->file, r, o->out);
      return 0;
    };
  });
}

}  // namespace polarcam::cli
