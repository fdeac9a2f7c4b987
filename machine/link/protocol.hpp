#pragma once
// The host-controller protocol (spec: docs/controller-protocol.md): frames, message types and their payloads.
// Pure: bytes in, messages out; no ports, no clocks.
//
// Frame: 0x7E | LEN (u8: bytes of SEQ..payload) | ~LEN | SEQ (u16 LE) | TYPE (u8) | payload | CRC-32 (LE, over
// LEN..payload). ~LEN rejects a damaged length at once, so a receiver never waits for bytes that will not come.
//
// The constants, the frame layout, the CRC and the payload layouts are machine/link/wire.hpp, which the reference
// firmware includes too; this file gives them the host's types (strings, doubles).
#include <cstdint>
#include <string>
#include <vector>

#include "machine/link/wire.hpp"

namespace polarcam::proto {

using wire::kMaxPayload;
using wire::kOverhead;
using wire::kSync;
using wire::kVersion;  // 5: tool items, IDENT's capabilities; 4: ACK and STATUS carry free bytes; 3: IDENT the largest step rate; 2: cubic runs
using wire::kUnlimited;

using wire::Type;
using wire::IDENTIFY, wire::CONFIGURE, wire::QUEUE, wire::START, wire::HOLD, wire::RESUME, wire::ABORT, wire::RESET,
    wire::STATUS, wire::ACK, wire::NAK, wire::IDENT, wire::STATUS_REPLY, wire::ERROR, wire::BOOT;
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

using wire::State;
const char* state_name(State s);

using wire::ErrorCode;

struct Ident {
  uint8_t version = kVersion;
  uint64_t tick_ps = 0;
  uint32_t slots = 0;
  uint32_t session = 0;
  uint32_t max_step_rate = 0;  // steps per second, both axes together, that the controller sustains (0: no limit)
  uint8_t caps = 0;            // capability bits: wire::kCapTool, it executes tool items
  std::string name;
  std::string encode() const;
  // false when malformed; out.version is set from the first byte even then (a controller of another version)
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
  uint32_t free_bytes = kUnlimited;  // room for this many bytes of encoded items (kUnlimited: items only)
  std::string encode() const;
  static bool decode(const std::string& p, Ack& out);
};

// The layout and fields are wire::Status's.
struct Status : wire::Status {
  std::string encode() const;
  static bool decode(const std::string& p, Status& out);
};

struct ErrorMsg {
  ErrorCode code = ErrorCode::none;
  std::string text;
  std::string encode() const;
  static bool decode(const std::string& p, ErrorMsg& out);
};

using wire::seq_diff;  // sequence arithmetic on u16: a - b in [-32768, 32767]

}  // namespace polarcam::proto
