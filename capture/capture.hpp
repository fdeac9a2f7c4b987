#pragma once
// Encoder capture (docs/capture.md): the radial and angular quadrature encoders of a machine or a template
// digitizer, recorded by a logic analyser (VCD or CSV, capture/levels.hpp), decoded into the machine's steps with
// their recorded times, and the tracing speed measured from them, as A. Fahim's thesis, Appendix D, analysed
// the template digitizer's encoder signals.
//
// Decoding, per axis (channels A and B): standard X4 quadrature. The levels (A, B) walk the Gray cycle
// 00 -> 10 -> 11 -> 01 -> 00 one count per edge: +1 along that order (A leads B), -1 against it. A change of
// both channels at one sample is an illegal transition: reported with its time and line and counted, the count
// left as it was (its direction is unknown), the new levels taken as the state. Counts become steps through
// counts_per_step c: the axis's step index is floor(count / c), and a step (+1 or -1) is emitted whenever a count
// moves it, at that edge's time (no hysteresis: a channel chattering across a multiple of c gives steps back
// and forth, as the encoder itself did). Decoding starts at the first sample where all four channels have a
// level, which is time 0 of the tape and count 0 of both axes.
// A step's time is its edge's time from that origin rounded to the tape's 1 ns tick (halves away from zero).
//
// Step/dir (the other encoding): per axis a STEP and a DIR channel, as a stepper driver reads them. One step per
// rising edge (0 -> 1) of STEP, +1 when DIR is high at that sample and -1 when it is low (the other way round on
// an axis whose polarity is inverted). DIR is read at the edge's sample, after the changes of that sample: a DIR
// change at the same recorded time as the edge counts for it. A DIR change less than the setup time before the
// edge (the driver's t_su) is no error: the step takes the level DIR has at the edge, and the edge is counted
// per axis (dir_setup_late). A STEP edge while DIR is unknown (x or z), or STEP rising out of an unknown level, is
// a glitch: reported with its time and line like an illegal transition, no step emitted.
// Either encoding: the origin (time 0) may instead be the first rising edge of a further signal (origin_signal,
// e.g. a controller's "running" output); a step before that edge is refused.
//
// The speed (Appendix D: "the time periods between the signals are used to calculate the contouring speed"):
// the path's speed over windows of N steps: the straight distance between the nodes after step i and after step
// i + N, over the time between those steps (a window ends at the first step at least N steps on whose time is
// later). Statistics over the whole windows: the time-weighted mean (the distance over the time), the median,
// the smallest and the largest with the time of their window's middle, and the stretches of consecutive windows
// off the median by more than a tolerance ("where it varied": the start, indentations of a template).
#include <cstdint>
#include <istream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "capture/levels.hpp"
#include "digitizer/digitize.hpp"
#include "digitizer/grid.hpp"
#include "digitizer/tape.hpp"

namespace polarcam {

enum class CaptureFormat { vcd, csv };
const char* to_string(CaptureFormat f);

// What the four channels are: two quadrature encoders (A and B per axis) or two step/direction pairs.
enum class CaptureEncoding { quadrature, step_dir };
const char* to_string(CaptureEncoding e);  // "quadrature", "step-dir"
// "quadrature" or "step-dir"; InputError naming --encoding otherwise.
CaptureEncoding parse_capture_encoding(const std::string& text);

// The four channels' names in the file (VCD signal names, with or without scopes; CSV column names): A and B of
// the radial and the angular encoder (quadrature), or STEP and DIR of each axis (step/dir).
struct CaptureSignals {
  std::string r_a = "r_a", r_b = "r_b", theta_a = "theta_a", theta_b = "theta_b";
  std::string r_step = "r_step", r_dir = "r_dir", theta_step = "theta_step", theta_dir = "theta_dir";
  // The encoding's four channels, in the order the decoder reads them (radial first, A or STEP first).
  std::vector<std::string> list(CaptureEncoding e = CaptureEncoding::quadrature) const {
    if (e == CaptureEncoding::step_dir) return {r_step, r_dir, theta_step, theta_dir};
    return {r_a, r_b, theta_a, theta_b};
  }
};
// The channels' own names of an encoding: r_a r_b theta_a theta_b, or r_step r_dir theta_step theta_dir.
std::vector<std::string> capture_channels(CaptureEncoding e);
// "r_a=CH0,theta_b=top.enc.B": the channels of encoding `e` renamed (any of the four, the others keep their
// default). InputError naming --signals for a channel of another encoding, an unknown one or a malformed pair.
CaptureSignals parse_capture_signals(const std::string& spec,
                                     CaptureEncoding e = CaptureEncoding::quadrature);

// The format: `given` ("vcd", "csv" or empty), else the file name's extension (.vcd, .csv), else the content
// (a VCD starts with a $command). InputError naming the file when none tells.
CaptureFormat capture_format(const std::string& given, const std::string& file, std::istream& in);

// One axis's quadrature decoder (exposed for tests).
class QuadratureDecoder {
 public:
  explicit QuadratureDecoder(int64_t counts_per_step = 1) : cps_(counts_per_step) {}
  // The first levels (the origin). Count 0.
  void start(int a, int b);
  enum Result { none = 0, counted = 1, illegal = 2 };
  // New levels of A and B: none (no change), counted (one count, +1 or -1, in `dir`; `step` is +1 or -1 when the
  // count moved the step index, else 0) or illegal (both channels changed).
  Result update(int a, int b, int& dir, int& step);
  int64_t count() const { return count_; }
  int64_t step_index() const { return step_; }
  int state() const { return state_; }  // Gray index 0..3 of (A, B): 00 0, 10 1, 11 2, 01 3

 private:
  int64_t cps_;
  int state_ = 0;
  int64_t count_ = 0, step_ = 0;
};

// One axis's step/dir decoder (exposed for tests). Levels are 0, 1 or -1 (unknown).
class StepDirDecoder {
 public:
  explicit StepDirDecoder(bool invert = false) : invert_(invert) {}
  // The first levels (the origin).
  void start(int step, int dir);
  enum Result { none = 0, stepped = 1, glitch = 2 };
  // New levels of STEP and DIR: none (no rising edge of STEP), stepped (a rising edge; `dir` +1 or -1) or
  // glitch (STEP rose with DIR unknown, or STEP came out of an unknown level to 1).
  Result update(int step, int dir_level, int& dir);
  int step_level() const { return step_; }
  int dir_level() const { return dir_; }

 private:
  bool invert_;
  int step_ = 0, dir_ = 0;
};

struct CaptureOptions {
  CaptureEncoding encoding = CaptureEncoding::quadrature;
  CaptureSignals signals;
  std::string origin_signal;      // time 0 at this signal's first rising edge (empty: all four channels known)
  bool invert_dir[2] = {false, false};  // step/dir: DIR high is the - direction on this axis
  int64_t dir_setup_ns = 650;     // step/dir: a DIR change closer than this before a STEP edge is counted late
  int64_t counts_per_step = 1;    // the machine file's counts_per_step (quadrature only)
  Grid grid;                      // the machine's grid (resolutions for the speed; the tape's header)
  double coupling = 0.0;          // m/rad: a coupled arm's radial motor (radius = n dR - coupling theta)
  int64_t start[2] = {0, 0};      // the node before the first step (the machine's home or --start)
  int window_steps = 100;         // N of the speed windows
  double speed_tolerance = 0.05;  // a window "varies" when off the median speed by more than this fraction
  size_t max_listed = 1000;       // illegal transitions and varied stretches kept in the lists (all counted)
};

struct IllegalTransition {
  int64_t t_ns = 0;      // from the origin
  uint64_t line = 0;     // the file's line
  int axis = 0;          // 0 radial, 1 angular
  int from = 0, to = 0;  // levels (A << 1) | B before and after (step/dir: (STEP << 1) | DIR)
  int unknown_from = 0, unknown_to = 0;  // step/dir: the bits of `from` and `to` that were unknown (x or z)
};
// "01", "1x": the levels of an illegal transition's `from` (or `to`) with its unknown bits.
std::string transition_levels(int levels, int unknown);

struct SpeedStretch {
  int64_t from_ns = 0, to_ns = 0;  // the first window's start, the last window's end
  double min_mps = 0, max_mps = 0;
  uint64_t windows = 0;
};

struct CaptureSpeed {
  int window_steps = 0;
  uint64_t windows = 0;
  double mean_mps = 0, median_mps = 0, min_mps = 0, max_mps = 0;
  int64_t min_at_ns = 0, max_at_ns = 0;  // the middle of the slowest and the fastest window
  double tolerance = 0;
  double steady_fraction = 0;   // the windows' time within tolerance of the median, over the windows' time
  uint64_t varied_windows = 0;
  uint64_t varied_stretches = 0;
  std::vector<SpeedStretch> varied;  // the first max_listed stretches
};

struct CaptureResult {
  CaptureFormat format = CaptureFormat::vcd;
  CaptureEncoding encoding = CaptureEncoding::quadrature;
  std::string origin_signal;          // the matched origin signal, when one was asked for
  std::vector<std::string> matched;  // the signals read (a VCD's full names; the CSV's columns)
  int64_t resolution_fs = 0;          // the recording's time resolution
  capture_i128 origin_fs = 0;         // the capture's time of the origin (as recorded)
  int64_t duration_ns = 0;            // origin to the last time the file holds
  uint64_t samples = 0;
  uint64_t counts_plus[2] = {0, 0}, counts_minus[2] = {0, 0};
  uint64_t illegal_total = 0, illegal_axis[2] = {0, 0};  // step/dir: the glitches
  std::vector<IllegalTransition> illegal;  // the first max_listed
  uint64_t dir_setup_late[2] = {0, 0};     // step/dir: steps whose DIR changed less than dir_setup_ns before
  int64_t dir_setup_late_first_ns = -1;    // the first of them (-1: none)
  uint64_t dir_setup_late_first_line = 0;
  uint64_t steps_plus[2] = {0, 0}, steps_minus[2] = {0, 0};
  int64_t start[2] = {0, 0}, end[2] = {0, 0};
  int64_t last_step_ns = 0;
  double path_length_m = 0;  // the chords from the start node through the windows' ends to the end node
  CaptureSpeed speed;
};

// Decodes the levels of `src` (signals r_a, r_b, theta_a, theta_b, or r_step, r_dir, theta_step, theta_dir, as
// bits 0..3; the origin signal, when asked for, as bit 4), emitting every step to `sink` (may be null).
// InputError when no sample has all four levels, the origin signal never rises, a step comes before it, or a
// time is beyond what a tape holds.
CaptureResult decode_levels(LevelSource& src, CaptureFormat format, const CaptureOptions& o, StepSink* sink);

// The whole capture from a stream: the reader of `format`, then decode_levels. `name` names the input in
// messages. The entry point for fuzzing: decode_capture(in, "fuzz", CaptureFormat::vcd, {}, nullptr) reads any
// bytes and either returns or throws InputError (default options: no grid, so every speed reads 0).
CaptureResult decode_capture(std::istream& in, const std::string& name, CaptureFormat format,
                             const CaptureOptions& o, StepSink* sink);

// Decodes `file` into a step tape at `tape` (not written when empty); the tape's provenance records
// `machine_provenance` (the machine's canonical description) and the capture's settings, never the file's name.
// InputError naming FILE:LINE for bad input, DeviceError for the output; no tape is left on failure.
// `also` (may be null) receives every step too (e.g. a TapeComparer).
CaptureResult capture_to_tape(const std::string& file, CaptureFormat format, const CaptureOptions& o,
                              const std::string& tape, const nlohmann::ordered_json& machine_provenance,
                              const std::string& generator, StepSink* also = nullptr);

// The grid (resolutions, steps per revolution, work area, home) and the start node of a tape's header, for a
// capture of that tape's play recorded without its machine file (a coupled arm's coupling is not on a tape: 0).
void use_tape_grid(const TapeHeader& h, CaptureOptions& o);

}  // namespace polarcam
