#include "capture/capture.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>

#include "cam/error.hpp"
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
  if (o.window_steps < 1 || o.window_steps > 1000000000)
    throw InputError("must be a whole number of steps from 1 to 10^9", "--window");
  if (!(o.speed_tolerance > 0) || !std::isfinite(o.speed_tolerance))
    throw InputError("must be a positive fraction (0.05 is 5 %)", "--speed-tolerance");
}

}  // namespace

const char* to_string(CaptureFormat f) { return f == CaptureFormat::vcd ? "vcd" : "csv"; }

CaptureSignals parse_capture_signals(const std::string& spec) {
  CaptureSignals s;
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
    if (ch == "r_a") s.r_a = name;
    else if (ch == "r_b") s.r_b = name;
    else if (ch == "theta_a") s.theta_a = name;
    else if (ch == "theta_b") s.theta_b = name;
    else throw InputError("unknown channel '" + ch + "': the channels are r_a, r_b, theta_a and theta_b", "--signals");
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

CaptureResult decode_levels(LevelSource& src, CaptureFormat format, const CaptureOptions& o, StepSink* sink) {
  check_options(o);
  CaptureResult r;
  r.format = format;
  for (int a = 0; a < 2; ++a) r.start[a] = r.end[a] = o.start[a];
  SpeedMeter meter(o, o.start);
  QuadratureDecoder dec[2] = {QuadratureDecoder(o.counts_per_step), QuadratureDecoder(o.counts_per_step)};
  LevelSample s;
  bool started = false;
  auto bit = [&](int i) { return static_cast<int>((s.levels >> i) & 1u); };
  while (src.next(s)) {
    if (!started) {
      if ((s.known & 15u) != 15u) continue;
      started = true;
      r.origin_fs = s.t_fs;
      r.samples = 1;
      dec[0].start(bit(0), bit(1));
      dec[1].start(bit(2), bit(3));
      continue;
    }
    ++r.samples;
    const capture_i128 d = s.t_fs - r.origin_fs;
    if (d > static_cast<capture_i128>(kMaxTimeNs) * 1000000)
      throw InputError("the time is more than 2^62 ns after the capture's start, beyond what a tape holds",
                       src.place(s.line));
    const int64_t t_ns = static_cast<int64_t>((d + 500000) / 1000000);
    for (int axis = 0; axis < 2; ++axis) {
      int dir = 0, step = 0;
      const int a = bit(2 * axis), b = bit(2 * axis + 1);
      const int before = dec[axis].state();
      const QuadratureDecoder::Result res = dec[axis].update(a, b, dir, step);
      if (res == QuadratureDecoder::counted) {
        ++(dir > 0 ? r.counts_plus : r.counts_minus)[axis];
        if (step != 0) {
          r.end[axis] += step;
          ++(step > 0 ? r.steps_plus : r.steps_minus)[axis];
          r.last_step_ns = t_ns;
          if (sink) sink->step(axis, step, t_ns);
          meter.step(r.end, t_ns);
        }
      } else if (res == QuadratureDecoder::illegal) {
        ++r.illegal_total;
        ++r.illegal_axis[axis];
        static constexpr int kLevels[4] = {0b00, 0b10, 0b11, 0b01};
        if (r.illegal.size() < o.max_listed) r.illegal.push_back({t_ns, s.line, axis, kLevels[before], (a << 1) | b});
      }
    }
  }
  if (!started)
    throw InputError("no time at which all four channels (" + o.signals.r_a + ", " + o.signals.r_b + ", " +
                         o.signals.theta_a + ", " + o.signals.theta_b +
                         ") have a level 0 or 1: record all four encoder channels",
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
  const std::vector<std::string> names = o.signals.list();
  if (format == CaptureFormat::vcd) {
    auto v = std::make_unique<VcdReader>(in, name, names);
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
  return r;
}

CaptureResult capture_to_tape(const std::string& file, CaptureFormat format, const CaptureOptions& o,
                              const std::string& tape, const nlohmann::ordered_json& machine_provenance,
                              const std::string& generator) {
  check_options(o);
  if (!(o.grid.dr > 0) || !(o.grid.dtheta > 0)) throw InputError("the machine's grid has no resolutions", "machine");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError("cannot be read: give a VCD or CSV file of the encoder levels", file);
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
    c["signals"] = {{"r_a", o.signals.r_a}, {"r_b", o.signals.r_b}, {"theta_a", o.signals.theta_a},
                    {"theta_b", o.signals.theta_b}};
    c["counts_per_step"] = o.counts_per_step;
    c["start_node"] = {o.start[0], o.start[1]};
    c["machine"] = machine_provenance;
    p["capture"] = c;
    h.provenance = p.dump();
    writer = std::make_unique<TapeWriter>(tape, h);
  }
  CaptureResult r = decode_levels(*src, format, o, writer.get());
  r.matched = std::move(matched);
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

}  // namespace polarcam
