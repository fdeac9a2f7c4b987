#pragma once
// The step tape: polarcam's one file format for timed axis steps (spec: docs/tape-format.md).
// A fixed little-endian header (format version, grid, work area, home, start/end nodes, totals, CRC-32s), a
// JSON provenance block (the job that made it), then one LEB128 varint per step:
//   value = (interval_ticks << 2) | (axis << 1) | (direction > 0)
// where interval_ticks is the time since the previous step (tick = 1 ns) and axis 0/1 is r/theta on a polar
// tape, x/y on a Cartesian one. Version 2 adds tool events (tool up, tool down) to the record stream: the two
// bytes 0x80 0x00 (an overlong zero, which no step is written as) followed by one varint
//   value = (interval_ticks << 2) | (down ? 1 : 0)
// and a tape without tool events is written as version 1, byte for byte as before. Writer and reader stream with O(1) memory; the writer writes to a temporary file
// and puts it in place only when the tape is complete (io/output.hpp: renamed over a file, copied into a device).
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "digitizer/digitize.hpp"
#include "io/output.hpp"

namespace polarcam {

inline constexpr uint16_t kTapeVersion = 1;         // a tape without tool events
inline constexpr uint16_t kTapeVersionEvents = 2;   // a tape with tool events (tool up / tool down)
inline constexpr uint32_t kTapeFixedHeader = 256;

enum class TapeAxes : uint8_t { polar = 0, cartesian = 1 };
// capture: steps decoded from a recorded run of the machine's encoders (capture/capture.hpp), not computed.
enum class TapeRule : uint8_t { nearest = 0, thesis = 1, dda = 2, exact_cartesian = 3, capture = 4 };
const char* to_string(TapeRule r);

struct TapeHeader {
  uint16_t version = kTapeVersion;
  TapeAxes axes = TapeAxes::polar;
  TapeRule rule = TapeRule::nearest;
  bool closed = false, returns_to_start = false;
  uint64_t tick_ps = 1000;          // tick length in picoseconds (1 ns)
  double res[2] = {0, 0};           // axis resolutions: m and rad (polar), m and m (Cartesian)
  int64_t steps_per_rev = 0;
  double r_min = 0;
  bool has_r_max = false, has_theta_range = false;
  double r_max = 0, theta_min = 0, theta_max = 0;
  int64_t home[2] = {0, 0};
  int64_t start[2] = {0, 0}, end[2] = {0, 0};
  uint64_t record_count = 0;
  uint64_t plus[2] = {0, 0}, minus[2] = {0, 0};
  uint64_t duration_ticks = 0;      // time to traverse the whole path
  uint64_t last_step_ticks = 0;     // cumulative time of the last step
  uint64_t records_bytes = 0;
  double speed_mps = 0, path_length_m = 0;
  uint32_t records_crc = 0, header_crc = 0;
  // version 2: the tool events in the record stream, and the tool's state before the first record (down unless
  // the header says up); events alternate from that state
  uint64_t event_count = 0;
  bool tool_starts_up = false;
  std::string provenance;           // JSON text
};

struct StepRecord {
  uint64_t interval = 0;  // ticks since the previous step
  int axis = 0;
  int dir = 1;
};

// A tool event of a version 2 tape: the tool lifted (down = false) or lowered (down = true) at t_ticks, the
// cumulative time from the start of the tape.
struct ToolEvent {
  uint64_t t_ticks = 0;
  bool down = false;
  uint64_t steps_before = 0;  // steps read before the event
};

class TapeWriter final : public StepSink {
 public:
  // Starts writing `path` (through a temporary file). `h.provenance` must be final now. DeviceError when `path`
  // cannot be an output (a missing directory, a directory).
  TapeWriter(const std::string& path, const TapeHeader& h);
  ~TapeWriter() override;  // removes the temporary file unless finish() succeeded
  TapeWriter(const TapeWriter&) = delete;
  TapeWriter& operator=(const TapeWriter&) = delete;

  void step(int axis, int dir, int64_t t_ns) override;
  void write(const StepRecord& r);  // raw record (interval already relative)
  // A tool event at t_ns (>= the last record's time). The tool starts down (or up when the constructor's header
  // says tool_starts_up); events must alternate (std::logic_error otherwise). A tape with events is version 2.
  void tool(bool down, int64_t t_ns) override;

  // Completes the header (caller's start/end nodes, durations and flags; the writer's own totals and CRCs),
  // checks that the end node equals the start node plus the steps written, and renames the file into place.
  // The version is 1 when no tool event was written (the bytes of a version 1 tape), else 2.
  void finish(TapeHeader h);

 private:
  void flush();
  std::string path_;
  std::unique_ptr<OutputFile> out_;
  std::FILE* f_ = nullptr;  // out_'s temporary
  std::vector<uint8_t> buf_;
  uint32_t crc_ = 0;
  uint64_t count_ = 0, bytes_ = 0, plus_[2] = {0, 0}, minus_[2] = {0, 0};
  int64_t last_ns_ = 0;
  uint64_t cum_ticks_ = 0;
  size_t header_size_ = 0;
  uint64_t events_ = 0;
  bool tool_starts_up_ = false, tool_down_ = true;
};

class TapeReader {
 public:
  // Opens and checks the header. Throws InputError (naming the file) for anything malformed.
  explicit TapeReader(const std::string& path);
  ~TapeReader();
  TapeReader(const TapeReader&) = delete;
  TapeReader& operator=(const TapeReader&) = delete;

  const TapeHeader& header() const { return h_; }
  // Next step; false after the last one, once the totals, byte count and CRC have been verified. A step's
  // interval is the time since the previous step (tool events between them included). Tool events of a version 2
  // tape (checked: they alternate, from the header's starting state) go to the handler; without a handler the
  // first one is an InputError ("this reader does not handle tool events").
  bool next(StepRecord& r) {
    // the usual record, inline: a varint of at most nine bytes, whole in the buffer, with every tool event read;
    // anything else (and every check that can fail but these two) in next_record()
    if (pos_ + 9 <= len_ && n_ < h_.record_count && events_ == h_.event_count) {
      const uint8_t* p = buf_.data() + pos_;
      uint64_t v = p[0] & 0x7f;
      size_t k = 1;
      for (; (p[k - 1] & 0x80) && k < 9; ++k) v |= static_cast<uint64_t>(p[k] & 0x7f) << (7 * k);
      if (!(p[k - 1] & 0x80) && (k == 1 || p[k - 1] != 0) && (v >> 2) <= max_ticks_ - cum_) {
        pos_ += k;
        accept(r, v);
        return true;
      }
    }
    return next_record(r);
  }
  // Receives the tool events of a version 2 tape, in order, as they are read.
  void on_tool_event(std::function<void(const ToolEvent&)> handler) { on_event_ = std::move(handler); }
  uint64_t events_read() const { return events_; }
  uint64_t records_read() const { return n_; }

 private:
  [[noreturn]] void fail(const std::string& what) const;
  void validate_header() const;     // InputError for values later arithmetic cannot hold
  uint64_t max_time_ticks() const;  // 2^62 ns in this tape's ticks
  uint64_t max_ticks_ = 0;           // the same, once the header is read
  bool next_record(StepRecord& r);
  // A step record's value v (interval << 2 | axis << 1 | plus), its interval checked: into r and the totals.
  void accept(StepRecord& r, uint64_t v) {
    const uint64_t interval = v >> 2;
    r.interval = interval + pending_;
    r.axis = static_cast<int>((v >> 1) & 1);
    r.dir = (v & 1) ? 1 : -1;
    ++n_;
    (r.dir > 0 ? plus_ : minus_)[r.axis] += 1;
    cum_ += interval;
    pending_ = 0;
  }
  bool fill();
  std::string path_;
  std::FILE* f_ = nullptr;
  TapeHeader h_;
  std::vector<uint8_t> buf_;
  size_t pos_ = 0, len_ = 0;
  [[noreturn]] void ran_out(const std::string& which) const;  // the records ended before `which`
  uint64_t n_ = 0, bytes_ = 0, cum_ = 0;
  uint64_t plus_[2] = {0, 0}, minus_[2] = {0, 0};
  uint32_t crc_ = 0;
  bool finished_ = false;
  uint64_t events_ = 0, pending_ = 0;  // events read; ticks of the events since the last step
  bool tool_down_ = true;
  std::function<void(const ToolEvent&)> on_event_;
};

// Reads the whole tape once and throws InputError if anything is wrong with it.
// Tool events are checked and counted.
TapeHeader verify_tape(const std::string& path);

// The radial motor steps per arm turn of a sand-table arm's coupling, as the tape's provenance records it
// ("job" / "machine" / "coupling_steps_per_rev"); 0 for a plain polar machine (or a provenance that says none).
// On such a tape the radial index is the radial motor's, q0 = r + c theta: the ball's radius is q0 - c theta.
double tape_coupling_steps_per_rev(const TapeHeader& h);

// For readers that do not handle tool events: InputError naming the tape, "<what> does not handle tool events
// (tool up / tool down): <advice>", when the tape carries any.
void refuse_tool_events(const TapeHeader& h, const std::string& path, const std::string& what, const std::string& advice);

}  // namespace polarcam
