#include "capture/capture.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>

#include "cam/error.hpp"
#include "cam/input_file.hpp"
#include "capture/csv_levels.hpp"
#include "capture/vcd.hpp"
#include "digitizer/tape.hpp"

namespace polarcam {
namespace {

constexpr int64_t kMaxTimeNs = int64_t{1} << 62;  // what a tape's times hold

// Gray index of the levels (A, B): 00 -> 0, 10 -> 1, 11 -> 2, 01 -> 3.
int gray(int a, int b) { return a ? (b ? 2 : 1) : (b ? 3 : 0); }

int64_t floor_div(int64_t a, int64_t b) {
  int64_t q = a / b;
  if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
  return q;
}

// The path's speed over windows of N steps, and its length through the windows' ends.
class SpeedMeter {
 public:
  SpeedMeter(const CaptureOptions& o, const int64_t start[2]) : o_(o) { point(start, p0_); chain_ = {p0_[0], p0_[1]}; }

  void step(const int64_t node[2], int64_t t_ns) {
    double p[2];
    point(node, p);
    if (!open_) {  // the first step opens the first window
      length_ += std::hypot(p[0] - chain_[0], p[1] - chain_[1]);
      chain_ = {p[0], p[1]};
      w0_ = {p[0], p[1]};
      t0_ = t_ns;
      open_ = true;
      return;
    }
    if (++k_ >= static_cast<uint64_t>(o_.window_steps) && t_ns > t0_) {
      const double d = std::hypot(p[0] - w0_[0], p[1] - w0_[1]);
      windows_.push_back({t0_, t_ns, d});
      length_ += d;
      chain_ = w0_ = {p[0], p[1]};
      t0_ = t_ns;
      k_ = 0;
    }
  }

  void finish(const int64_t end[2], CaptureResult& r) const {
    double p[2];
    point(end, p);
    r.path_length_m = length_ + std::hypot(p[0] - chain_[0], p[1] - chain_[1]);
    CaptureSpeed& s = r.speed;
    s.window_steps = o_.window_steps;
    s.tolerance = o_.speed_tolerance;
    s.windows = windows_.size();
    if (windows_.empty()) return;
    double len = 0, time = 0;
    std::vector<double> v;
    v.reserve(windows_.size());
    for (const Window& w : windows_) {
      len += w.length;
      time += static_cast<double>(w.t1 - w.t0) * 1e-9;
      v.push_back(w.speed());
    }
    s.mean_mps = len / time;
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    const size_t n = sorted.size();
    s.median_mps = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    s.min_mps = s.max_mps = v[0];
    s.min_at_ns = s.max_at_ns = windows_[0].middle();
    double steady = 0;
    bool in = false, listed = false;
    for (size_t i = 0; i < windows_.size(); ++i) {
      const Window& w = windows_[i];
      if (v[i] < s.min_mps) s.min_mps = v[i], s.min_at_ns = w.middle();
      if (v[i] > s.max_mps) s.max_mps = v[i], s.max_at_ns = w.middle();
      const bool varies = std::abs(v[i] - s.median_mps) > o_.speed_tolerance * s.median_mps;
      if (!varies) {
        steady += static_cast<double>(w.t1 - w.t0) * 1e-9;
        in = false;
        continue;
      }
      ++s.varied_windows;
      if (!in) {  // a new stretch
        ++s.varied_stretches;
        in = true;
        listed = s.varied.size() < o_.max_listed;
        if (listed) s.varied.push_back({w.t0, w.t1, v[i], v[i], 0});
      }
      if (listed) {
        SpeedStretch& st = s.varied.back();
        st.to_ns = w.t1;
        st.min_mps = std::min(st.min_mps, v[i]);
        st.max_mps = std::max(st.max_mps, v[i]);
        ++st.windows;
      }
    }
    s.steady_fraction = steady / time;
  }

 private:
  struct Window {
    int64_t t0, t1;
    double length;
    double speed() const { return length / (static_cast<double>(t1 - t0) * 1e-9); }
    int64_t middle() const { return t0 + (t1 - t0) / 2; }
  };
  void point(const int64_t node[2], double p[2]) const {
    const double th = static_cast<double>(node[1]) * o_.grid.dtheta;
    const double r = static_cast<double>(node[0]) * o_.grid.dr - o_.coupling * th;
    p[0] = r * std::cos(th);
    p[1] = r * std::sin(th);
  }
  const CaptureOptions& o_;
  double p0_[2] = {0, 0};
  std::array<double, 2> chain_{}, w0_{};
  bool open_ = false;
  int64_t t0_ = 0;
  uint64_t k_ = 0;
  double length_ = 0;
  std::vector<Window> windows_;
};

void check_options(const CaptureOptions& o) {
  if (o.counts_per_step < 1) throw InputError("counts_per_step must be a whole number from 1", "counts_per_step");
  if (o.dir_setup_ns < 0 || o.dir_setup_ns > 1000000000)
    throw InputError("must be a time from 0 to 1 s (e.g. \"650 ns\")", "--dir-setup");
  if (o.window_steps < 1 || o.window_steps > 1000000000)
    throw InputError("must be a whole number of steps from 1 to 10^9", "--window");
  if (!(o.speed_tolerance > 0) || !std::isfinite(o.speed_tolerance))
    throw InputError("must be a positive fraction (0.05 is 5 %)", "--speed-tolerance");
}

}  // namespace

const char* to_string(CaptureFormat f) { return f == CaptureFormat::vcd ? "vcd" : "csv"; }

const char* to_string(CaptureEncoding e) { return e == CaptureEncoding::step_dir ? "step-dir" : "quadrature"; }

CaptureEncoding parse_capture_encoding(const std::string& text) {
  if (text == "quadrature") return CaptureEncoding::quadrature;
  if (text == "step-dir") return CaptureEncoding::step_dir;
  throw InputError("'" + text + "' is not an encoding: give quadrature (A and B per axis) or step-dir (STEP and "
                   "DIR per axis)", "--encoding");
}

std::vector<std::string> capture_channels(CaptureEncoding e) { return CaptureSignals{}.list(e); }

std::string transition_levels(int levels, int unknown) {
  std::string t;
  for (int bit = 1; bit >= 0; --bit) t += (unknown >> bit) & 1 ? 'x' : static_cast<char>('0' + ((levels >> bit) & 1));
  return t;
}

CaptureSignals parse_capture_signals(const std::string& spec, CaptureEncoding e) {
  CaptureSignals s;
  const bool sd = e == CaptureEncoding::step_dir;
  const std::vector<std::string> own = capture_channels(e);
  const std::vector<std::string> other =
      capture_channels(sd ? CaptureEncoding::quadrature : CaptureEncoding::step_dir);
  const std::string own_list = own[0] + ", " + own[1] + ", " + own[2] + " and " + own[3];
  size_t i = 0;
  while (i <= spec.size()) {
    size_t j = spec.find(',', i);
    if (j == std::string::npos) j = spec.size();
    const std::string pair = spec.substr(i, j - i);
    const size_t eq = pair.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == pair.size())
      throw InputError("'" + pair + "' is not CHANNEL=NAME (e.g. --signals r_a=D0,r_b=D1,theta_a=D2,theta_b=D3)",
                       "--signals");
    const std::string ch = pair.substr(0, eq), name = pair.substr(eq + 1);
    if (!sd && ch == "r_a") s.r_a = name;
    else if (!sd && ch == "r_b") s.r_b = name;
    else if (!sd && ch == "theta_a") s.theta_a = name;
    else if (!sd && ch == "theta_b") s.theta_b = name;
    else if (sd && ch == "r_step") s.r_step = name;
    else if (sd && ch == "r_dir") s.r_dir = name;
    else if (sd && ch == "theta_step") s.theta_step = name;
    else if (sd && ch == "theta_dir") s.theta_dir = name;
    else if (std::find(other.begin(), other.end(), ch) != other.end())
      throw InputError("channel '" + ch + "' is not one of the " + to_string(e) + " encoding's (" + own_list +
                           "): give --encoding " + (sd ? "quadrature" : "step-dir") + " for it",
                       "--signals");
    else throw InputError("unknown channel '" + ch + "': the channels are " + own_list, "--signals");
    i = j + 1;
  }
  return s;
}

CaptureFormat capture_format(const std::string& given, const std::string& file, std::istream& in) {
  if (given == "vcd") return CaptureFormat::vcd;
  if (given == "csv") return CaptureFormat::csv;
  if (!given.empty()) throw InputError("'" + given + "' is not a capture format: give vcd or csv", "--format");
  auto ends = [&](const std::string& ext) {
    if (file.size() < ext.size()) return false;
    for (size_t i = 0; i < ext.size(); ++i)
      if (std::tolower(static_cast<unsigned char>(file[file.size() - ext.size() + i])) != ext[i]) return false;
    return true;
  };
  if (ends(".vcd")) return CaptureFormat::vcd;
  if (ends(".csv")) return CaptureFormat::csv;
  std::streambuf* b = in.rdbuf();
  for (int i = 0; b && i < 4096; ++i) {  // peek at the first non-blank character, then rewind
    const int c = b->sbumpc();
    if (c == std::char_traits<char>::eof()) break;
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') continue;
    in.clear();
    in.seekg(0);
    if (c == '$') return CaptureFormat::vcd;
    break;
  }
  in.clear();
  in.seekg(0);
  throw InputError("not a VCD file (it does not start with a $command) and not named .vcd or .csv: give --format vcd "
                   "or --format csv", file);
}

void QuadratureDecoder::start(int a, int b) {
  state_ = gray(a, b);
  count_ = 0;
  step_ = 0;
}

QuadratureDecoder::Result QuadratureDecoder::update(int a, int b, int& dir, int& step) {
  dir = 0;
  step = 0;
  const int g = gray(a, b);
  const int d = (g - state_) & 3;
  state_ = g;
  if (d == 0) return none;
  if (d == 2) return illegal;
  dir = d == 1 ? 1 : -1;
  count_ += dir;
  const int64_t s = floor_div(count_, cps_);
  if (s != step_) {
    step = static_cast<int>(s - step_);
    step_ = s;
  }
  return counted;
}

void StepDirDecoder::start(int step, int dir) {
  step_ = step;
  dir_ = dir;
}

StepDirDecoder::Result StepDirDecoder::update(int step, int dir_level, int& dir) {
  dir = 0;
  const int before = step_;
  step_ = step;
  dir_ = dir_level;
  if (step != 1 || before == 1) return none;  // no rising edge
  if (before < 0 || dir_level < 0) return glitch;
  dir = (dir_level == 1) != invert_ ? 1 : -1;
  return stepped;
}

CaptureResult decode_levels(LevelSource& src, CaptureFormat format, const CaptureOptions& o, StepSink* sink) {
  check_options(o);
  CaptureResult r;
  r.format = format;
  r.encoding = o.encoding;
  const bool sd = o.encoding == CaptureEncoding::step_dir;
  const bool has_origin = !o.origin_signal.empty();
  for (int a = 0; a < 2; ++a) r.start[a] = r.end[a] = o.start[a];
  SpeedMeter meter(o, o.start);
  QuadratureDecoder dec[2] = {QuadratureDecoder(o.counts_per_step), QuadratureDecoder(o.counts_per_step)};
  StepDirDecoder sdd[2] = {StepDirDecoder(o.invert_dir[0]), StepDirDecoder(o.invert_dir[1])};
  capture_i128 dir_changed_fs[2] = {0, 0};
  bool dir_changed[2] = {false, false};
  const capture_i128 setup_fs = static_cast<capture_i128>(o.dir_setup_ns) * 1000000;
  LevelSample s;
  bool started = false, origin = !has_origin, origin_low = false;
  auto bit = [&](int i) { return static_cast<int>((s.levels >> i) & 1u); };
  auto level = [&](int i) { return (s.known >> i) & 1u ? bit(i) : -1; };
  int64_t t_ns = 0;
  auto before_origin = [&] {
    throw InputError(std::string("a step before the first rising edge of the origin signal '") + o.origin_signal +
                         "': the recording must start before that edge (or give no origin signal)",
                     src.place(s.line));
  };
  auto emit = [&](int axis, int step) {
    if (!origin) before_origin();
    r.end[axis] += step;
    ++(step > 0 ? r.steps_plus : r.steps_minus)[axis];
    r.last_step_ns = t_ns;
    if (sink) sink->step(axis, step, t_ns);
    meter.step(r.end, t_ns);
  };
  auto illegal = [&](const IllegalTransition& t) {
    if (!origin) before_origin();
    ++r.illegal_total;
    ++r.illegal_axis[t.axis];
    if (r.illegal.size() < o.max_listed) r.illegal.push_back(t);
  };
  while (src.next(s)) {
    if (!origin) {  // the origin signal's first rising edge (from a level 0) is time 0
      if ((s.changed & 16u) && (s.levels & 16u) && origin_low) {
        origin = true;
        r.origin_fs = s.t_fs;
      }
      origin_low = (s.known & 16u) && !(s.levels & 16u);
    }
    if (!started) {
      if ((s.known & 15u) != 15u) continue;
      started = true;
      if (!has_origin) r.origin_fs = s.t_fs;
      r.samples = 1;
      if (sd) {
        sdd[0].start(bit(0), bit(1));
        sdd[1].start(bit(2), bit(3));
      } else {
        dec[0].start(bit(0), bit(1));
        dec[1].start(bit(2), bit(3));
      }
      continue;
    }
    ++r.samples;
    if (origin) {
      const capture_i128 d = s.t_fs - r.origin_fs;
      if (d > static_cast<capture_i128>(kMaxTimeNs) * 1000000)
        throw InputError("the time is more than 2^62 ns after the capture's start, beyond what a tape holds",
                         src.place(s.line));
      t_ns = static_cast<int64_t>((d + 500000) / 1000000);
    }
    for (int axis = 0; axis < 2; ++axis) {
      if (sd) {
        const int st = level(2 * axis), dl = level(2 * axis + 1);
        const int from = (std::max(sdd[axis].step_level(), 0) << 1) | std::max(sdd[axis].dir_level(), 0);
        const int from_unknown = (sdd[axis].step_level() < 0 ? 2 : 0) | (sdd[axis].dir_level() < 0 ? 1 : 0);
        if (s.changed & (2u << (2 * axis))) {
          dir_changed[axis] = true;
          dir_changed_fs[axis] = s.t_fs;
        }
        int dir = 0;
        const StepDirDecoder::Result res = sdd[axis].update(st, dl, dir);
        if (res == StepDirDecoder::stepped) {
          ++(dir > 0 ? r.counts_plus : r.counts_minus)[axis];
          if (dir_changed[axis] && s.t_fs - dir_changed_fs[axis] < setup_fs) {
            if (r.dir_setup_late[0] + r.dir_setup_late[1] == 0) {
              r.dir_setup_late_first_ns = t_ns;
              r.dir_setup_late_first_line = s.line;
            }
            ++r.dir_setup_late[axis];
          }
          emit(axis, dir);
        } else if (res == StepDirDecoder::glitch) {
          const int to = (std::max(st, 0) << 1) | std::max(dl, 0);
          const int to_unknown = (st < 0 ? 2 : 0) | (dl < 0 ? 1 : 0);
          illegal({t_ns, s.line, axis, from, to, from_unknown, to_unknown});
        }
        continue;
      }
      int dir = 0, step = 0;
      const int a = bit(2 * axis), b = bit(2 * axis + 1);
      const int before = dec[axis].state();
      const QuadratureDecoder::Result res = dec[axis].update(a, b, dir, step);
      if (res == QuadratureDecoder::counted) {
        ++(dir > 0 ? r.counts_plus : r.counts_minus)[axis];
        if (step != 0) emit(axis, step);
      } else if (res == QuadratureDecoder::illegal) {
        static constexpr int kLevels[4] = {0b00, 0b10, 0b11, 0b01};
        illegal({t_ns, s.line, axis, kLevels[before], (a << 1) | b, 0, 0});
      }
    }
  }
  if (!started) {
    const std::vector<std::string> ch = o.signals.list(o.encoding);
    throw InputError("no time at which all four channels (" + ch[0] + ", " + ch[1] + ", " + ch[2] + ", " + ch[3] +
                         ") have a level 0 or 1: record all four " + (sd ? "step and direction" : "encoder") +
                         " channels",
                     src.place(0));
  }
  if (!origin)
    throw InputError("the origin signal '" + o.origin_signal +
                         "' never rises from 0 to 1: record it from before the run starts, or give no origin signal",
                     src.place(0));
  r.resolution_fs = src.resolution_fs();
  const capture_i128 end = src.end_fs() - r.origin_fs;
  if (end > static_cast<capture_i128>(kMaxTimeNs) * 1000000)
    throw InputError("the capture lasts more than 2^62 ns, beyond what a tape holds", src.place(0));
  r.duration_ns = std::max(r.last_step_ns, static_cast<int64_t>((std::max<capture_i128>(end, 0) + 500000) / 1000000));
  meter.finish(r.end, r);
  return r;
}

namespace {

std::unique_ptr<LevelSource> make_reader(std::istream& in, const std::string& name, CaptureFormat format,
                                         const CaptureOptions& o, std::vector<std::string>& matched) {
  std::vector<std::string> names = o.signals.list(o.encoding);
  if (!o.origin_signal.empty()) names.push_back(o.origin_signal);
  if (format == CaptureFormat::vcd) {
    // step/dir: a channel may go back to x or z (a STEP edge met by an unknown DIR is reported as a glitch);
    // the origin signal may too (only its first rising edge counts)
    auto v = std::make_unique<VcdReader>(in, name, names, o.encoding == CaptureEncoding::step_dir ? 31u : 16u);
    matched = v->matched();
    return v;
  }
  matched = names;
  return std::make_unique<CsvLevelReader>(in, name, names);
}

}  // namespace

CaptureResult decode_capture(std::istream& in, const std::string& name, CaptureFormat format,
                             const CaptureOptions& o, StepSink* sink) {
  std::vector<std::string> matched;
  std::unique_ptr<LevelSource> src = make_reader(in, name, format, o, matched);
  CaptureResult r = decode_levels(*src, format, o, sink);
  r.matched = std::move(matched);
  if (r.matched.size() > 4) {
    r.origin_signal = r.matched.back();
    r.matched.pop_back();
  }
  return r;
}

CaptureResult capture_to_tape(const std::string& file, CaptureFormat format, const CaptureOptions& o,
                              const std::string& tape, const nlohmann::ordered_json& machine_provenance,
                              const std::string& generator, StepSink* also) {
  check_options(o);
  if (!(o.grid.dr > 0) || !(o.grid.dtheta > 0)) throw InputError("the machine's grid has no resolutions", "machine");
  std::ifstream in = open_input_file(file, "cannot be read: give a VCD or CSV file of the encoder levels");
  std::vector<std::string> matched;
  std::unique_ptr<LevelSource> src = make_reader(in, file, format, o, matched);
  std::unique_ptr<TapeWriter> writer;
  TapeHeader h;
  if (!tape.empty()) {
    const Grid& g = o.grid;
    h.axes = TapeAxes::polar;
    h.rule = TapeRule::capture;
    h.res[0] = g.dr;
    h.res[1] = g.dtheta;
    h.steps_per_rev = g.steps_per_rev;
    h.r_min = g.r_min;
    h.has_r_max = g.r_max.has_value();
    h.r_max = g.r_max.value_or(0.0);
    h.has_theta_range = g.theta_min.has_value();
    h.theta_min = g.theta_min.value_or(0.0);
    h.theta_max = g.theta_max.value_or(0.0);
    h.home[0] = g.home_n();
    h.home[1] = g.home_m();
    h.start[0] = o.start[0];
    h.start[1] = o.start[1];
    nlohmann::ordered_json p, c;
    p["generator"] = generator;
    c["format"] = to_string(format);
    c["encoding"] = to_string(o.encoding);
    const std::vector<std::string> ch = capture_channels(o.encoding), names = o.signals.list(o.encoding);
    nlohmann::ordered_json sig;
    for (size_t i = 0; i < ch.size(); ++i) sig[ch[i]] = names[i];
    c["signals"] = sig;
    if (!o.origin_signal.empty()) c["origin_signal"] = o.origin_signal;
    if (o.encoding == CaptureEncoding::step_dir) {
      c["invert_dir"] = {o.invert_dir[0], o.invert_dir[1]};
      c["dir_setup_ns"] = o.dir_setup_ns;
    } else {
      c["counts_per_step"] = o.counts_per_step;
    }
    c["start_node"] = {o.start[0], o.start[1]};
    c["machine"] = machine_provenance;
    p["capture"] = c;
    h.provenance = p.dump();
    writer = std::make_unique<TapeWriter>(tape, h);
  }
  struct Tee final : StepSink {
    StepSink* a;
    StepSink* b;
    void step(int axis, int dir, int64_t t_ns) override {
      if (a) a->step(axis, dir, t_ns);
      if (b) b->step(axis, dir, t_ns);
    }
  } tee;
  tee.a = writer.get();
  tee.b = also;
  CaptureResult r = decode_levels(*src, format, o, &tee);
  r.matched = std::move(matched);
  if (r.matched.size() > 4) {
    r.origin_signal = r.matched.back();
    r.matched.pop_back();
  }
  if (writer) {
    h.end[0] = r.end[0];
    h.end[1] = r.end[1];
    h.duration_ticks = static_cast<uint64_t>(r.duration_ns);
    h.speed_mps = r.speed.mean_mps;
    h.path_length_m = r.path_length_m;
    h.closed = false;
    // the same place: the same radius, and the arm turned by whole turns (as the digitizer's tapes say it)
    const int64_t turn = o.grid.steps_per_rev;
    h.returns_to_start = r.end[0] == r.start[0] &&
                         (turn > 0 ? (r.end[1] - r.start[1]) % turn == 0 : r.end[1] == r.start[1]);
    writer->finish(h);
  }
  return r;
}

void use_tape_grid(const TapeHeader& h, CaptureOptions& o) {
  Grid g;
  g.dr = h.res[0];
  g.dtheta = h.res[1];
  g.steps_per_rev = h.steps_per_rev;
  g.r_min = h.r_min;
  if (h.has_r_max) g.r_max = h.r_max;
  if (h.has_theta_range) {
    g.theta_min = h.theta_min;
    g.theta_max = h.theta_max;
  }
  g.home_r = static_cast<double>(h.home[0]) * h.res[0];
  g.home_theta = static_cast<double>(h.home[1]) * h.res[1];
  o.grid = g;
  o.coupling = 0.0;
  o.start[0] = h.start[0];
  o.start[1] = h.start[1];
}

}  // namespace polarcam
