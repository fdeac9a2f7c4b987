// polarcam capture FILE --machine M [-o OUT.tape] [--encoding quadrature|step-dir] [--signals ...]
//                  [--format vcd|csv] [--origin SIGNAL] [--invert-dir AXES] [--dir-setup T] [--start R,THETA]
//                  [--window N] [--speed-tolerance F] [--compare TAPE [--speed-scale K] [--tick T] [--tolerance T]]
//                  [--json]
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "cam/format.hpp"
#include "cam/input_file.hpp"
#include "capture/capture.hpp"
#include "capture/tape_compare.hpp"
#include "machine/player/scaling.hpp"
#include "io/output.hpp"

#ifndef POLARCAM_VERSION
#define POLARCAM_VERSION "0.0.0"
#endif

namespace polarcam::cli {
namespace cmd_capture {  // named, not anonymous: the command files are compiled together (unity build)

const char* kAxis[2] = {"radial", "angular"};


double seconds(int64_t ns) { return static_cast<double>(ns) * 1e-9; }

std::string num(double v, int digits = 6) { return polarcam::significant(v, digits); }

struct Comparing {
  std::string tape;
  Ratio speed;
  TapeCompareOptions options;
  TapeComparison result;
};

nlohmann::ordered_json comparison_json(const Comparing& c) {
  const TapeComparison& t = c.result;
  nlohmann::ordered_json j;
  j["tape"] = c.tape;
  j["speed_scale"] = to_string(c.speed);
  j["tick_ns"] = c.options.tick_ns;
  j["tolerance_ns"] = c.options.tolerance_ns;
  j["steps_expected"] = t.steps_expected;
  j["steps_seen"] = t.steps_seen;
  j["matched"] = t.matched;
  j["mismatches"] = t.mismatches();
  j["order_mismatches"] = t.order_mismatches;
  j["time_mismatches"] = t.time_mismatches;
  j["missing"] = t.steps_expected > t.steps_seen ? t.steps_expected - t.steps_seen : 0;
  j["extra"] = t.steps_seen > t.steps_expected ? t.steps_seen - t.steps_expected : 0;
  j["simultaneous_swapped"] = t.simultaneous_swapped;
  j["max_time_error_ns"] = t.max_time_error_ns;
  j["worst_step"] = t.worst_step;
  j["max_raw_error_ns"] = t.max_raw_error_ns;
  j["max_jitter_ns"] = t.max_jitter_ns;
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const TapeMismatch& m : t.listed) {
    nlohmann::ordered_json e;
    e["kind"] = to_string(m.kind);
    e["step"] = m.index;
    if (m.kind != TapeMismatch::extra)
      e["expected"] = {{"axis", kAxis[m.expected_axis]}, {"dir", m.expected_dir}, {"t_ns", m.expected_ns}};
    if (m.kind != TapeMismatch::missing)
      e["seen"] = {{"axis", kAxis[m.seen_axis]}, {"dir", m.seen_dir}, {"t_ns", m.seen_ns}};
    if (m.kind == TapeMismatch::time) e["error_ns"] = m.error_ns;
    list.push_back(e);
  }
  j["listed"] = list;
  j["result"] = t.ok() ? "PASS" : "FAIL";
  return j;
}

nlohmann::ordered_json summary_json(const CaptureResult& r, const CaptureOptions& o, const std::string& out,
                                    const Comparing* cmp) {
  nlohmann::ordered_json j;
  const bool sd = r.encoding == CaptureEncoding::step_dir;
  j["format"] = to_string(r.format);
  j["encoding"] = to_string(r.encoding);
  const std::vector<std::string> channels = capture_channels(r.encoding);
  nlohmann::ordered_json sig;
  for (size_t i = 0; i < channels.size(); ++i) sig[channels[i]] = r.matched.at(i);
  j["signals"] = sig;
  if (!r.origin_signal.empty()) j["origin_signal"] = r.origin_signal;
  j["resolution_s"] = static_cast<double>(r.resolution_fs) * 1e-15;
  j["tick_s"] = 1e-9;
  j["origin_s"] = static_cast<double>(r.origin_fs) * 1e-15;
  j["duration_s"] = seconds(r.duration_ns);
  j["samples"] = r.samples;
  if (sd) {
    j["invert_dir"] = {{"radial", o.invert_dir[0]}, {"angular", o.invert_dir[1]}};
    j["dir_setup_s"] = static_cast<double>(o.dir_setup_ns) * 1e-9;
    j["dir_setup_late"] = {{"radial", r.dir_setup_late[0]},
                           {"angular", r.dir_setup_late[1]},
                           {"first_s", r.dir_setup_late_first_ns < 0 ? nlohmann::ordered_json(nullptr)
                                                                     : nlohmann::ordered_json(seconds(r.dir_setup_late_first_ns))}};
  } else {
    j["counts_per_step"] = o.counts_per_step;
  }
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
    list.push_back({{"t_s", seconds(t.t_ns)}, {"line", t.line}, {"axis", kAxis[t.axis]},
                    {"from", transition_levels(t.from, t.unknown_from)}, {"to", transition_levels(t.to, t.unknown_to)}});
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
  if (cmp) j["comparison"] = comparison_json(*cmp);
  return j;
}

std::string summary_text(const std::string& file, const CaptureResult& r, const std::string& out,
                         const Comparing* cmp) {
  std::ostringstream os;
  const bool sd = r.encoding == CaptureEncoding::step_dir;
  os << "polarcam capture " << file << " (" << to_string(r.format) << ", " << to_string(r.encoding)
     << ", resolution " << num(static_cast<double>(r.resolution_fs) * 1e-15) << " s";
  if (!r.origin_signal.empty()) os << ", time 0 at the rising edge of " << r.origin_signal;
  os << ")\n";
  for (int a = 0; a < 2; ++a) {
    os << "  " << (a ? "angular" : "radial ") << "    ";
    if (!sd) os << "counts +" << thousands(r.counts_plus[a]) << " / -" << thousands(r.counts_minus[a]) << ", ";
    os << "steps +" << thousands(r.steps_plus[a]) << " / -" << thousands(r.steps_minus[a]) << ", "
       << (sd ? "glitches " : "illegal transitions ") << thousands(r.illegal_axis[a]);
    if (sd) os << ", direction set late " << thousands(r.dir_setup_late[a]);
    os << "\n";
  }
  for (size_t i = 0; i < r.illegal.size() && i < 10; ++i) {
    const IllegalTransition& t = r.illegal[i];
    os << "  " << (sd ? "glitch     " : "illegal    ") << kAxis[t.axis] << " "
       << transition_levels(t.from, t.unknown_from) << " -> " << transition_levels(t.to, t.unknown_to) << " at "
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
  if (cmp) {
    const TapeComparison& t = cmp->result;
    os << "  compared   with " << cmp->tape << " at speed scale " << to_string(cmp->speed) << ": "
       << thousands(t.steps_seen) << " steps seen of " << thousands(t.steps_expected) << ", "
       << thousands(t.mismatches()) << " mismatches, largest time error " << num(t.max_time_error_ns) << " ns";
    if (cmp->options.tick_ns > 0) os << " on ticks of " << cmp->options.tick_ns << " ns";
    os << " (tolerance " << cmp->options.tolerance_ns << " ns): " << (t.ok() ? "PASS" : "FAIL") << "\n";
    for (size_t i = 0; i < t.listed.size() && i < 10; ++i) {
      const TapeMismatch& m = t.listed[i];
      os << "  mismatch   step " << m.index << " " << to_string(m.kind) << ":";
      if (m.kind != TapeMismatch::extra)
        os << " expected " << kAxis[m.expected_axis] << " " << (m.expected_dir > 0 ? "+" : "-") << " at "
           << num(m.expected_ns * 1e-9, 10) << " s";
      if (m.kind != TapeMismatch::missing)
        os << " seen " << kAxis[m.seen_axis] << " " << (m.seen_dir > 0 ? "+" : "-") << " at "
           << num(seconds(m.seen_ns), 10) << " s";
      os << "\n";
    }
  }
  return os.str();
}

// "4us", "650 ns": a time option in whole nanoseconds.
int64_t option_ns(const std::string& text, const std::string& option) {
  const double t = option_quantity(text, dim::time, option);
  if (!(t >= 0) || !(t <= 1000.0)) throw InputError("must be a time from 0 to 1000 s (e.g. \"4 us\")", option);
  return static_cast<int64_t>(std::llround(t * 1e9));
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

}  // namespace cmd_capture

void register_capture(CLI::App& app, Action& action) {
  using namespace cmd_capture;
  struct Opts {
    std::string file, out, machine, signals, format, start, encoding = "quadrature", origin, invert_dir,
        dir_setup = "650 ns", compare, speed = "1", tick, time_tolerance;
    int window = 100;
    double tolerance = 0.05;
    bool json = false;
    CLI::Option* dir_setup_opt = nullptr;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "capture",
      "Decode two quadrature encoders or two step/dir pairs recorded by a logic analyser (VCD or CSV) into a step "
      "tape; compare it with a tape");
  c->add_option("file", o->file, "the recording: a VCD file, or a CSV of time_s and the four levels")->required();
  c->add_option("--machine", o->machine,
                "machine file (grid, home, counts_per_step); with --compare, default: the compared tape's grid");
  c->add_option("-o,--output", o->out, "write the step tape to this file");
  c->add_option("--encoding", o->encoding,
                "quadrature (A and B per axis, default) or step-dir (STEP and DIR per axis: a step per rising edge "
                "of STEP, + when DIR is high)");
  c->add_option("--signals", o->signals,
                "the channels' names in the file, e.g. r_a=D0,r_b=D1,theta_a=D2,theta_b=D3 (default r_a r_b "
                "theta_a theta_b; step-dir: r_step r_dir theta_step theta_dir)");
  c->add_option("--origin", o->origin,
                "time 0 at the first rising edge of this signal (default: the first time all four channels have "
                "a level)");
  c->add_option("--invert-dir", o->invert_dir, "step-dir: axes whose DIR high is the - direction: r, theta or r,theta");
  o->dir_setup_opt = c->add_option("--dir-setup", o->dir_setup,
                "step-dir: a DIR change closer than this before a STEP edge is counted as late (default 650 ns)");
  c->add_option("--compare", o->compare,
                "compare the steps with this tape: every step, in order, axis, direction and time (exit 1 when "
                "they differ)");
  c->add_option("--speed-scale", o->speed, "with --compare: the tape was played at this speed scale (K or P/Q)");
  c->add_option("--tick", o->tick,
                "with --compare: the controller's tick; the seen times are taken to the nearest tick from time 0");
  c->add_option("--tolerance", o->time_tolerance,
                "with --compare: the largest time error accepted (default: one --tick, else 0)");
  c->add_option("--format", o->format, "vcd or csv (default: from the file name, else the content)");
  c->add_option("--start", o->start, "the node before the first step, as R,THETA (default: the machine's home)");
  c->add_option("--window", o->window, "steps per speed window (default 100)");
  c->add_option("--speed-tolerance", o->tolerance,
                "a window varies when off the median speed by more than this fraction (default 0.05)");
  c->add_flag("--json", o->json, "print the counts, illegal transitions and speed statistics as one JSON object");
  c->callback([o, &action] {
    action = [o] {
      CaptureOptions co;
      co.encoding = parse_capture_encoding(o->encoding);
      const bool sd = co.encoding == CaptureEncoding::step_dir;
      if (!o->signals.empty()) co.signals = parse_capture_signals(o->signals, co.encoding);
      co.origin_signal = o->origin;
      if (!o->invert_dir.empty()) {
        if (!sd) throw InputError("applies to --encoding step-dir only (swap A and B to invert an encoder)", "--invert-dir");
        if (o->invert_dir == "r") co.invert_dir[0] = true;
        else if (o->invert_dir == "theta") co.invert_dir[1] = true;
        else if (o->invert_dir == "r,theta" || o->invert_dir == "theta,r") co.invert_dir[0] = co.invert_dir[1] = true;
        else throw InputError("'" + o->invert_dir + "' is not r, theta or r,theta", "--invert-dir");
      }
      if (!sd && option_given(o->dir_setup_opt))
        throw InputError("applies to --encoding step-dir only (an encoder has no direction line)", "--dir-setup");
      co.dir_setup_ns = option_ns(o->dir_setup, "--dir-setup");
      if (o->machine.empty() && o->compare.empty())
        throw InputError("give the machine file (--machine M.toml), or --compare TAPE to take the grid from that tape",
                         "--machine");
      if (o->compare.empty() && (!o->tick.empty() || !o->time_tolerance.empty() || o->speed != "1"))
        throw InputError("applies with --compare TAPE only",
                         !o->tick.empty() ? "--tick" : !o->time_tolerance.empty() ? "--tolerance" : "--speed-scale");
      if (o->window < 1) throw InputError("must be a whole number of steps from 1", "--window");
      co.window_steps = o->window;
      if (!(o->tolerance > 0) || !std::isfinite(o->tolerance))
        throw InputError("must be a positive fraction (0.05 is 5 %)", "--speed-tolerance");
      co.speed_tolerance = o->tolerance;
      if (!o->format.empty() && o->format != "vcd" && o->format != "csv")
        throw InputError("'" + o->format + "' is not a capture format: give vcd or csv", "--format");
      std::unique_ptr<Comparing> cmp;
      std::unique_ptr<TapeComparer> comparer;
      if (!o->compare.empty()) {
        cmp = std::make_unique<Comparing>();
        cmp->tape = o->compare;
        cmp->speed = parse_ratio(o->speed, "--speed-scale");
        cmp->options.speed_num = cmp->speed.num;
        cmp->options.speed_den = cmp->speed.den;
        if (!o->tick.empty()) cmp->options.tick_ns = option_ns(o->tick, "--tick");
        cmp->options.tolerance_ns = o->time_tolerance.empty() ? cmp->options.tick_ns : option_ns(o->time_tolerance, "--tolerance");
        comparer = std::make_unique<TapeComparer>(o->compare, cmp->options);
        if (comparer->expected().header().axes != TapeAxes::polar)
          throw InputError("is a Cartesian tape: a capture gives polar steps; compare it with a polar tape", o->compare);
      }
      nlohmann::ordered_json prov;
      if (!o->machine.empty()) {
        const Machine m = load_machine(o->machine, &prov);
        co.grid = m.grid;
        co.coupling = m.coupling;
        co.counts_per_step = m.counts_per_step;
        co.start[0] = m.grid.home_n();
        co.start[1] = m.grid.home_m();
        if (comparer) {  // the run played that tape: it began at its start node
          co.start[0] = comparer->expected().header().start[0];
          co.start[1] = comparer->expected().header().start[1];
        }
      } else {
        use_tape_grid(comparer->expected().header(), co);
        prov = {{"grid", "the compared tape's"}};
      }
      if (sd && co.counts_per_step != 1)
        std::fprintf(stderr,
                     "note: the machine's counts_per_step (%lld) does not apply to step/dir: one STEP pulse is one "
                     "step\n",
                     static_cast<long long>(co.counts_per_step));
      if (sd) co.counts_per_step = 1;
      if (!o->start.empty()) start_node(o->start, co.grid, co.start);
      if (!o->out.empty()) check_output_path(o->out);
      CaptureFormat format;
      {
        std::ifstream in = open_input_file(o->file, "cannot be read: give a VCD or CSV file of the encoder levels");
        format = capture_format(o->format, o->file, in);
      }
      const CaptureResult r = capture_to_tape(o->file, format, co, o->out, prov,
                                              std::string("polarcam ") + POLARCAM_VERSION, comparer.get());
      if (cmp) cmp->result = comparer->finish();
      if (r.illegal_total && !sd)  // reported, never dropped silently: on the terminal even with --json
        std::fprintf(stderr,
                     "warning: %llu illegal transition%s (both channels of an encoder changed at once; their counts "
                     "are lost), the first on the %s encoder at %s s (%s:%llu)\n",
                     static_cast<unsigned long long>(r.illegal_total), r.illegal_total == 1 ? "" : "s",
                     kAxis[r.illegal.front().axis],
                     num(seconds(r.illegal.front().t_ns), 10).c_str(), o->file.c_str(),
                     static_cast<unsigned long long>(r.illegal.front().line));
      if (r.illegal_total && sd)
        std::fprintf(stderr,
                     "warning: %llu glitch%s (a STEP edge with DIR unknown, or out of an unknown level; no step "
                     "taken), the first on the %s axis at %s s (%s:%llu)\n",
                     static_cast<unsigned long long>(r.illegal_total), r.illegal_total == 1 ? "" : "es",
                     kAxis[r.illegal.front().axis],
                     num(seconds(r.illegal.front().t_ns), 10).c_str(), o->file.c_str(),
                     static_cast<unsigned long long>(r.illegal.front().line));
      if (o->json)
        std::cout << summary_json(r, co, o->out, cmp.get()).dump(2) << "\n";
      else
        std::cout << summary_text(o->file, r, o->out, cmp.get());
      return cmp && !cmp->result.ok() ? 1 : 0;
    };
  });
}

}  // namespace polarcam::cli
