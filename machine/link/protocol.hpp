#pragma once
// The host-controller protocol (spec: docs/controller-protocol.md): frames, message types and their payloads.
// Pure: bytes in, messages out; no ports, no clocks.
//
// Frame: 0x7E | LEN (u8: bytes of SEQ..payload) | ~LEN | SEQ (u16 LE) | TYPE (u8) | payload | CRC-32 (LE, over
// LEN..payload). ~LEN rejects a damaged length at once, so a receiver never waits for bytes that will not come.
#include <cstdint>
#include <string>
#include <vector>

namespace polarcam::proto {

inline constexpr uint8_t kSync = 0x7E;
inline constexpr size_t kMaxPayload = 240;
inline constexpr size_t kOverhead = 1 + 2 + 2 + 1 + 4;
inline constexpr uint8_t kVersion = 2;  // 2: cubic runs with an offset (docs/controller-protocol.md)

enum Type : uint8_t {
  // host -> controller; QUEUE and START are sequenced (exactly once, in order), the others carry a request id
  IDENTIFY = 0x01, CONFIGURE = 0x02, QUEUE = 0x03, START = 0x04, HOLD = 0x05, RESUME = 0x06, ABORT = 0x07,
  RESET = 0x08, STATUS = 0x09,
  // controller -> host
  ACK = 0x81, NAK = 0x82, IDENT = 0x83, STATUS_REPLY = 0x84, ERROR = 0x85, BOOT = 0x86,
};
const char* type_name(uint8_t t);

struct Frame {
  uint16_t seq = 0;
  uint8_t type = 0;
  std::string payload;
};

std::string encode_frame(uint16_t seq, uint8_t type, const std::string& payload);

// Reassembles frames from a byte stream with losses and damage: resynchronises on the sync byte, checks LEN and
// the CRC, and skips one byte and rescans after any bad frame.
class FrameDecoder {
 public:
  void feed(const uint8_t* data, size_t n, std::vector<Frame>& out);
  uint64_t bad_frames() const { return bad_; }
  uint64_t skipped_bytes() const { return skipped_; }
  void clear() { buf_.clear(); }

 private:
  std::string buf_;
  uint64_t bad_ = 0, skipped_ = 0;
};

// Little-endian payload writer/reader.
struct Writer {
  std::string s;
  Writer& u8(uint8_t v) { s.push_back(static_cast<char>(v)); return *this; }
  Writer& u16(uint16_t v) { return raw(v, 2); }
  Writer& u32(uint32_t v) { return raw(v, 4); }
  Writer& u64(uint64_t v) { return raw(v, 8); }
  Writer& i64(int64_t v) { return raw(static_cast<uint64_t>(v), 8); }
  Writer& f64(double v);
  Writer& str(const std::string& v);  // u8 length + bytes (at most 200)
  Writer& raw(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
    return *this;
  }
};
struct Reader {
  const std::string& s;
  size_t pos = 0;
  bool ok = true;
  uint64_t raw(int n);
  uint8_t u8() { return static_cast<uint8_t>(raw(1)); }
  uint16_t u16() { return static_cast<uint16_t>(raw(2)); }
  uint32_t u32() { return static_cast<uint32_t>(raw(4)); }
  uint64_t u64() { return raw(8); }
  int64_t i64() { return static_cast<int64_t>(raw(8)); }
  double f64();
  std::string str();
  bool done() const { return ok && pos == s.size(); }
};

// ---- payloads ------------------------------------------------------------------------------------------

enum class State : uint8_t { idle = 0, ready = 1, running = 2, holding = 3, held = 4, resuming = 5, stopping = 6,
                             underrun = 7, done = 8, aborted = 9, fault = 10 };
const char* state_name(State s);

enum class ErrorCode : uint8_t { none = 0, busy = 1, bad_config = 2, grid_mismatch = 3, bad_queue = 4,
                                 overflow = 5, not_configured = 6, bad_state = 7 };

struct Ident {
  uint8_t version = kVersion;
  uint64_t tick_ps = 0;
  uint32_t slots = 0;
  uint32_t session = 0;
  std::string name;
  std::string encode() const;
  static bool decode(const std::string& p, Ident& out);
};

struct Configure {
  uint64_t tick_ps = 0;       // must equal the controller's
  uint8_t axes = 2;
  uint64_t ramp_ticks = 0;    // hold/resume/underrun ramp: playback rate 1 -> 0 (or back) over this many ticks
  int64_t start[2] = {0, 0};  // axis positions (machine nodes) before the first step
  double dr = 0, dtheta = 0;  // the grid the tape was made for (0: not checked)
  std::string encode() const;
  static bool decode(const std::string& p, Configure& out);
};

struct Ack {
  uint16_t next_seq = 0;   // every sequenced frame before this one has been received
  uint32_t free_slots = 0;
  uint8_t state = 0;
  std::string encode() const;
  static bool decode(const std::string& p, Ack& out);
};

struct Status {
  State state = State::idle;
  ErrorCode error = ErrorCode::none;
  uint32_t underruns = 0;
  uint64_t now_ticks = 0;        // controller time since START (when done: the time of the last step)
  uint64_t schedule_ticks = 0;   // schedule (virtual) time reached
  uint32_t free_slots = 0, queued = 0;
  uint64_t executed[2] = {0, 0};
  int64_t node[2] = {0, 0};
  uint16_t next_seq = 0;
  uint32_t session = 0;
  uint32_t bad_frames = 0;
  std::string encode() const;
  static bool decode(const std::string& p, Status& out);
};

struct ErrorMsg {
  ErrorCode code = ErrorCode::none;
  std::string text;
  std::string encode() const;
  static bool decode(const std::string& p, ErrorMsg& out);
};

// sequence arithmetic on u16: a - b in [-32768, 32767]
inline int seq_diff(uint16_t a, uint16_t b) { return static_cast<int16_t>(static_cast<uint16_t>(a - b)); }

}  // namespace polarcam::proto
