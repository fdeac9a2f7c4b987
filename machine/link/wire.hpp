#pragma once
// The wire of the host-controller protocol (docs/controller-protocol.md), shared by polarcam and the reference
// firmware (firmware/) so that the two cannot drift: constants, message types, states and errors, the frame
// layout and its CRC-32, the payload layouts, and the step schedule's items (their validity, the per-axis
// prediction, the byte encoding, and the arithmetic that executes a run).
//
// Plain C++14 without the standard library: it compiles with avr-g++ 5.4 (8-bit AVR, no STL, 32-bit double) as
// with the host's compiler. Everything is inline; nothing allocates; buffers are the caller's.
#include <stddef.h>
#include <stdint.h>

namespace polarcam {
namespace wire {

// ---- constants -------------------------------------------------------------------------------------------

// 5: tool items in the queue (the tool up or down at a schedule tick), IDENT carries capability bits; 4: ACK and
// STATUS_REPLY carry the queue's free bytes (credits in bytes as well as items), NAK whether the frames after the
// missing one were kept; 3: IDENT carries the controller's largest sustained step rate; 2: cubic runs with an
// offset.
static constexpr uint8_t kVersion = 5;
// IDENT's capability bits
static constexpr uint8_t kCapTool = 1;  // executes tool items (drives a tool: a pen lift, a spindle, a Z axis)
static constexpr uint32_t kUnlimited = 0xffffffffu;  // free_bytes of a controller whose queue counts items only
// A controller that counts bytes sends an ACK unasked when its free bytes have grown by this much since its last
// ACK (a window update): a host with no room left learns of the new room without a STATUS round trip.
static constexpr uint32_t kWindowUpdate = 32;
static constexpr uint8_t kSync = 0x7E;
static constexpr size_t kMaxPayload = 240;
static constexpr size_t kHeader = 6;                 // sync, LEN, ~LEN, SEQ lo, SEQ hi, TYPE
static constexpr size_t kOverhead = kHeader + 4;     // + CRC-32
static constexpr size_t kMaxFrame = kMaxPayload + kOverhead;
static constexpr size_t kMaxName = 200;              // strings in payloads (u8 length + bytes)

enum Type : uint8_t {
  // host -> controller; QUEUE and START are sequenced (exactly once, in order), the others carry a request id
  IDENTIFY = 0x01, CONFIGURE = 0x02, QUEUE = 0x03, START = 0x04, HOLD = 0x05, RESUME = 0x06, ABORT = 0x07,
  RESET = 0x08, STATUS = 0x09,
  // controller -> host
  ACK = 0x81, NAK = 0x82, IDENT = 0x83, STATUS_REPLY = 0x84, ERROR = 0x85, BOOT = 0x86,
};

enum class State : uint8_t { idle = 0, ready = 1, running = 2, holding = 3, held = 4, resuming = 5, stopping = 6,
                             underrun = 7, done = 8, aborted = 9, fault = 10 };

enum class ErrorCode : uint8_t { none = 0, busy = 1, bad_config = 2, grid_mismatch = 3, bad_queue = 4,
                                 overflow = 5, not_configured = 6, bad_state = 7 };

// sequence arithmetic on u16: a - b in [-32768, 32767]
inline int seq_diff(uint16_t a, uint16_t b) { return static_cast<int16_t>(static_cast<uint16_t>(a - b)); }

// ---- CRC-32 (zlib's: reflected polynomial 0xEDB88320), four bits at a time ---------------------------------

// The running CRC of bytes p[0..n) continued from `crc` (0 to begin), as zlib's crc32(crc, p, n).
inline uint32_t crc32(uint32_t crc, const uint8_t* p, size_t n) {
  static const uint32_t kNibble[16] = {
      0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu, 0x76DC4190u, 0x6B6B51F4u, 0x4DB26158u, 0x5005713Cu,
      0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu, 0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu};
  crc = ~crc;
  for (size_t i = 0; i < n; ++i) {
    crc ^= p[i];
    crc = (crc >> 4) ^ kNibble[crc & 15];
    crc = (crc >> 4) ^ kNibble[crc & 15];
  }
  return ~crc;
}

// ---- little-endian fields ----------------------------------------------------------------------------------

inline void put_le(uint8_t* p, uint64_t v, int n) {
  for (int i = 0; i < n; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
inline uint64_t get_le(const uint8_t* p, int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(p[i]) << (8 * i);
  return v;
}

// Writes fields into a caller's buffer; ok turns false (and nothing more is written) when it would overflow.
struct Put {
  uint8_t* p;
  size_t cap;
  size_t n = 0;
  bool ok = true;
  Put(uint8_t* buf, size_t capacity) : p(buf), cap(capacity) {}
  Put& raw(uint64_t v, int k) {
    if (!ok || n + static_cast<size_t>(k) > cap) {
      ok = false;
      return *this;
    }
    put_le(p + n, v, k);
    n += static_cast<size_t>(k);
    return *this;
  }
  Put& u8(uint8_t v) { return raw(v, 1); }
  Put& u16(uint16_t v) { return raw(v, 2); }
  Put& u32(uint32_t v) { return raw(v, 4); }
  Put& u64(uint64_t v) { return raw(v, 8); }
  Put& i64(int64_t v) { return raw(static_cast<uint64_t>(v), 8); }
  // u8 length + bytes (at most kMaxName)
  Put& str(const char* s, size_t len) {
    if (len > kMaxName) len = kMaxName;
    u8(static_cast<uint8_t>(len));
    if (!ok || n + len > cap) {
      ok = false;
      return *this;
    }
    for (size_t i = 0; i < len; ++i) p[n + i] = static_cast<uint8_t>(s[i]);
    n += len;
    return *this;
  }
};

// Reads fields; ok turns false (and every later field reads 0) when the payload is too short.
struct Get {
  const uint8_t* p;
  size_t len;
  size_t pos = 0;
  bool ok = true;
  Get(const uint8_t* data, size_t n) : p(data), len(n) {}
  uint64_t raw(int k) {
    if (!ok || pos + static_cast<size_t>(k) > len) {
      ok = false;
      return 0;
    }
    const uint64_t v = get_le(p + pos, k);
    pos += static_cast<size_t>(k);
    return v;
  }
  uint8_t u8() { return static_cast<uint8_t>(raw(1)); }
  uint16_t u16() { return static_cast<uint16_t>(raw(2)); }
  uint32_t u32() { return static_cast<uint32_t>(raw(4)); }
  uint64_t u64() { return raw(8); }
  int64_t i64() { return static_cast<int64_t>(raw(8)); }
  // u8 length + bytes: points into the payload
  const char* str(size_t& n) {
    n = u8();
    if (!ok || pos + n > len) {
      ok = false;
      n = 0;
      return "";
    }
    const char* s = reinterpret_cast<const char*>(p + pos);
    pos += n;
    return s;
  }
  bool done() const { return ok && pos == len; }
};

// ---- frames --------------------------------------------------------------------------------------------
//
// 0x7E | LEN | ~LEN | SEQ lo | SEQ hi | TYPE | payload (LEN - 3 bytes) | CRC-32 (LE, over LEN .. payload)

// LEN and ~LEN of a frame start: LEN counts SEQ, TYPE and the payload.
inline bool frame_len_ok(uint8_t len, uint8_t not_len) {
  return len >= 3 && len <= kMaxPayload + 3 && not_len == static_cast<uint8_t>(~len);
}
// Bytes of the whole frame of length field `len`.
inline size_t frame_size(uint8_t len) { return 3 + static_cast<size_t>(len) + 4; }
// A whole frame at f (f[0] the sync byte, f[1] its LEN, already checked): true when its CRC is right.
inline bool frame_crc_ok(const uint8_t* f) {
  const uint8_t len = f[1];
  return static_cast<uint32_t>(get_le(f + 3 + len, 4)) == crc32(0, f + 1, 2 + static_cast<size_t>(len));
}
inline uint16_t frame_seq(const uint8_t* f) { return static_cast<uint16_t>(f[3] | static_cast<uint16_t>(f[4]) << 8); }
inline uint8_t frame_type(const uint8_t* f) { return f[5]; }
inline const uint8_t* frame_payload(const uint8_t* f) { return f + kHeader; }
inline size_t frame_payload_size(const uint8_t* f) { return static_cast<size_t>(f[1]) - 3; }

// Writes the frame into out (room for n + kOverhead bytes; n <= kMaxPayload) and returns its size. The payload
// may already be in place at out + kHeader (payload == out + kHeader): it is not copied then.
inline size_t frame_encode(uint8_t* out, uint16_t seq, uint8_t type, const uint8_t* payload, size_t n) {
  out[0] = kSync;
  out[1] = static_cast<uint8_t>(n + 3);
  out[2] = static_cast<uint8_t>(~(n + 3));
  out[3] = static_cast<uint8_t>(seq & 0xff);
  out[4] = static_cast<uint8_t>(seq >> 8);
  out[5] = type;
  if (payload != out + kHeader)
    for (size_t i = 0; i < n; ++i) out[kHeader + i] = payload[i];
  put_le(out + kHeader + n, crc32(0, out + 1, n + 5), 4);
  return n + kOverhead;
}

// ---- payloads ------------------------------------------------------------------------------------------

// IDENT: version u8, tick_ps u64, slots u32, session u32, max_step_rate u32, caps u8, name (u8 length + bytes).
// A decoder reads the version first: a controller of another version is named, not misread.
struct Ident {
  uint8_t version = kVersion;
  uint64_t tick_ps = 0;         // the controller's timer tick
  uint32_t slots = 0;           // queue items it buffers
  uint32_t session = 0;         // changes at every boot
  uint32_t max_step_rate = 0;   // steps per second (both axes together) it sustains; 0: not limited
  uint8_t caps = 0;             // capability bits (kCapTool)
  const char* name = "";
  size_t name_len = 0;
  size_t encode(uint8_t* out, size_t cap) const {
    Put w(out, cap);
    w.u8(version).u64(tick_ps).u32(slots).u32(session).u32(max_step_rate).u8(caps).str(name, name_len);
    return w.ok ? w.n : 0;
  }
  // false when malformed; `version` is set whenever the payload has a first byte
  bool decode(const uint8_t* p, size_t n) {
    Get r(p, n);
    version = r.u8();
    if (!r.ok || version != kVersion) return false;
    tick_ps = r.u64();
    slots = r.u32();
    session = r.u32();
    max_step_rate = r.u32();
    caps = r.u8();
    name = r.str(name_len);
    return r.done();
  }
};

// CONFIGURE: tick_ps u64, axes u8, ramp_ticks u64, start node n i64, m i64, dR f64, dtheta f64 (the doubles as
// their IEEE 754 bits: the firmware only passes them on).
struct Configure {
  uint64_t tick_ps = 0;
  uint8_t axes = 2;
  uint64_t ramp_ticks = 0;
  int64_t start[2] = {0, 0};
  uint64_t dr_bits = 0, dtheta_bits = 0;
  static constexpr size_t kSize = 8 + 1 + 8 + 8 + 8 + 8 + 8;
  size_t encode(uint8_t* out, size_t cap) const {
    Put w(out, cap);
    w.u64(tick_ps).u8(axes).u64(ramp_ticks).i64(start[0]).i64(start[1]).u64(dr_bits).u64(dtheta_bits);
    return w.ok ? w.n : 0;
  }
  bool decode(const uint8_t* p, size_t n) {
    Get r(p, n);
    tick_ps = r.u64();
    axes = r.u8();
    ramp_ticks = r.u64();
    start[0] = r.i64();
    start[1] = r.i64();
    dr_bits = r.u64();
    dtheta_bits = r.u64();
    return r.done();
  }
};

// ACK: next_seq u16 (every sequenced frame before it received), free_slots u32, state u8, free_bytes u32 (room
// for this many more bytes of encoded items; kUnlimited: items are the only limit).
struct Ack {
  uint16_t next_seq = 0;
  uint32_t free_slots = 0;
  uint8_t state = 0;
  uint32_t free_bytes = kUnlimited;
  static constexpr size_t kSize = 11;
  size_t encode(uint8_t* out, size_t cap) const {
    Put w(out, cap);
    w.u16(next_seq).u32(free_slots).u8(state).u32(free_bytes);
    return w.ok ? w.n : 0;
  }
  bool decode(const uint8_t* p, size_t n) {
    Get r(p, n);
    next_seq = r.u16();
    free_slots = r.u32();
    state = r.u8();
    free_bytes = r.u32();
    return r.done();
  }
};

// STATUS_REPLY: state u8, error u8, underruns u32, now_ticks u64, schedule_ticks u64, free_slots u32, queued u32,
// executed r u64, theta u64, node r i64, theta i64, next_seq u16, session u32, bad_frames u32, free_bytes u32.
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
  uint32_t free_bytes = kUnlimited;  // as ACK's
  static constexpr size_t kSize = 1 + 1 + 4 + 8 + 8 + 4 + 4 + 8 + 8 + 8 + 8 + 2 + 4 + 4 + 4;
  size_t encode(uint8_t* out, size_t cap) const {
    Put w(out, cap);
    w.u8(static_cast<uint8_t>(state)).u8(static_cast<uint8_t>(error)).u32(underruns).u64(now_ticks)
        .u64(schedule_ticks).u32(free_slots).u32(queued).u64(executed[0]).u64(executed[1]).i64(node[0])
        .i64(node[1]).u16(next_seq).u32(session).u32(bad_frames).u32(free_bytes);
    return w.ok ? w.n : 0;
  }
  bool decode(const uint8_t* p, size_t n) {
    Get r(p, n);
    const uint8_t st = r.u8(), er = r.u8();
    if (st > static_cast<uint8_t>(State::fault)) return false;
    state = static_cast<State>(st);
    error = static_cast<ErrorCode>(er);
    underruns = r.u32();
    now_ticks = r.u64();
    schedule_ticks = r.u64();
    free_slots = r.u32();
    queued = r.u32();
    executed[0] = r.u64();
    executed[1] = r.u64();
    node[0] = r.i64();
    node[1] = r.i64();
    next_seq = r.u16();
    session = r.u32();
    bad_frames = r.u32();
    free_bytes = r.u32();
    return r.done();
  }
};

// NAK: next_seq u16 (the sequenced frame the controller is missing), kept u8 (1: it keeps the frames that arrive
// after the missing one; 0: it drops them, and the host sends them again with the missing one).
struct Nak {
  uint16_t next_seq = 0;
  uint8_t kept = 1;
  static constexpr size_t kSize = 3;
  size_t encode(uint8_t* out, size_t cap) const {
    Put w(out, cap);
    w.u16(next_seq).u8(kept);
    return w.ok ? w.n : 0;
  }
  bool decode(const uint8_t* p, size_t n) {
    Get r(p, n);
    next_seq = r.u16();
    kept = r.u8();
    return r.done() && kept <= 1;
  }
};

// ERROR: code u8, text (u8 length + bytes). BOOT: session u32.
inline size_t encode_error(uint8_t* out, size_t cap, ErrorCode code, const char* text, size_t len) {
  Put w(out, cap);
  w.u8(static_cast<uint8_t>(code)).str(text, len);
  return w.ok ? w.n : 0;
}

// ---- the step schedule: items, their validity, the prediction, the encoding ---------------------------------

static constexpr int kFracBits = 32;
static constexpr int64_t kOneTick = int64_t{1} << kFracBits;
static constexpr int64_t kMaxIntervalFx = int64_t{1} << 62;   // 2^30 ticks: longer gaps use a wait
static constexpr int64_t kAddLimit = int64_t{1} << 62;
static constexpr uint32_t kMaxRunCount = 65535;
static constexpr size_t kMaxItemBytes = 1 + 3 + 2 + 4 * 10;   // tag, count, shifts, four varints

// tool (version 5): the tool goes down or up when the schedule time reaches a tick, after the steps of that tick
// and before those of later ticks; it holds no axis clock (the host leaves the tool its time in the steps' ticks).
enum class ItemKind : uint8_t { run = 0, wait = 1, end = 2, tool = 3 };

struct QueueItem {
  ItemKind kind = ItemKind::run;
  uint8_t axis = 0;
  int8_t dir = 1;            // run; tool: +1 down, -1 up
  uint32_t count = 0;        // run: steps
  int64_t offset = 0;        // run: clock shift before the first step (the first interval is offset + interval)
  int64_t interval = 0;      // run: interval of the progression's first step, 32.32 ticks
  int64_t add = 0;           // run: interval change per step, 32.32 ticks
  int64_t add2 = 0;          // run: change of the add per step, 32.32 ticks
  uint64_t wait = 0;         // wait: whole ticks; tool: the schedule tick (since START) at which it acts
};

// Signed 128-bit values for the validity checks, in plain 64-bit arithmetic (avr-gcc has no __int128).
struct Wide {
  uint64_t lo = 0;
  int64_t hi = 0;
  static Wide of(int64_t v) {
    Wide w;
    w.lo = static_cast<uint64_t>(v);
    w.hi = v < 0 ? -1 : 0;
    return w;
  }
  Wide operator+(const Wide& o) const {
    Wide r;
    r.lo = lo + o.lo;
    r.hi = static_cast<int64_t>(static_cast<uint64_t>(hi) + static_cast<uint64_t>(o.hi) + (r.lo < lo ? 1 : 0));
    return r;
  }
  Wide operator-() const {
    Wide r;
    r.lo = ~lo + 1;
    r.hi = static_cast<int64_t>(~static_cast<uint64_t>(hi) + (r.lo == 0 ? 1 : 0));
    return r;
  }
  // v * m for |v| <= 2^63, m < 2^32
  static Wide mul(int64_t v, uint32_t m) {
    const bool neg = v < 0;
    const uint64_t a = neg ? ~static_cast<uint64_t>(v) + 1 : static_cast<uint64_t>(v);
    const uint64_t lo = (a & 0xffffffffu) * m, hi = (a >> 32) * m;  // a * m = hi * 2^32 + lo
    Wide r;
    r.lo = lo + (hi << 32);
    r.hi = static_cast<int64_t>((hi >> 32) + (r.lo < lo ? 1 : 0));
    return neg ? -r : r;
  }
  bool operator<(const Wide& o) const { return hi != o.hi ? hi < o.hi : lo < o.lo; }
};

// A run is valid when its first interval (offset + interval) and every later interval lie in [one tick,
// kMaxIntervalFx] and every add A + (k-1) B (k = 1..n) and B lie within 2^62 in magnitude: then 64-bit
// arithmetic executes it without overflow and an axis never steps twice in one tick. Waits and ends are valid.
inline bool run_is_valid(const QueueItem& r) {
  if (r.kind != ItemKind::run) return true;
  if (r.count == 0 || r.count > kMaxRunCount) return false;
  const int64_t I = r.interval, A = r.add, B = r.add2;
  const Wide lo = Wide::of(kOneTick), hi = Wide::of(kMaxIntervalFx);
  auto in_range = [&](const Wide& iv) { return !(iv < lo) && !(hi < iv); };
  if (!in_range(Wide::of(r.offset) + Wide::of(I))) return false;
  if (B < -kAddLimit || B > kAddLimit || A < -kAddLimit || A > kAddLimit) return false;
  const uint32_t n = r.count;
  const Wide last_add = Wide::of(A) + Wide::mul(B, n - 1);
  if (last_add < Wide::of(-kAddLimit) || Wide::of(kAddLimit) < last_add) return false;
  if (n == 1) return true;
  // intervals q(j) = I + j A + C(j,2) B of steps j + 1, j = 1..n-1: a parabola, so both ends and its vertex
  auto q = [&](uint32_t j) { return Wide::of(I) + Wide::mul(A, j) + Wide::mul(B, j * (j - 1) / 2); };
  if (!in_range(q(1)) || !in_range(q(n - 1))) return false;
  if (B != 0) {
    // q(j+1) - q(j) = A + j B changes sign near j = -A / B (floored; |A|, |B| <= 2^62)
    int64_t v = -A / B;
    if ((-A % B != 0) && ((-A < 0) != (B < 0))) --v;
    for (int64_t j = v - 1; j <= v + 1; ++j)
      if (j >= 1 && j <= static_cast<int64_t>(n) - 1 && !in_range(q(static_cast<uint32_t>(j)))) return false;
  }
  return true;
}

// The next run as the wire predicts it: the previous run of the axis continued by one step (interval
// I + n A + C(n,2) B, add A + n B, second add B), in wrapping 64-bit arithmetic.
struct RunRef {
  int64_t interval = 0, add = 0, add2 = 0;
};
inline RunRef continuation(const QueueItem& r) {
  const uint64_t n = r.count, c2 = n * (n - 1) / 2;
  RunRef c;
  c.interval = static_cast<int64_t>(static_cast<uint64_t>(r.interval) + n * static_cast<uint64_t>(r.add) +
                                    c2 * static_cast<uint64_t>(r.add2));
  c.add = static_cast<int64_t>(static_cast<uint64_t>(r.add) + n * static_cast<uint64_t>(r.add2));
  c.add2 = r.add2;
  return c;
}

// The controller's arithmetic of one run, shared by every party.
struct RunCursor {
  uint32_t left = 0;
  int64_t offset = 0, iv = 0, add = 0, add2 = 0;
  bool first = true;
  void begin(const QueueItem& it) {
    left = it.count;
    offset = it.offset;
    iv = it.interval;
    add = it.add;
    add2 = it.add2;
    first = true;
  }
  // The clock advance to the next step of the run (left > 0).
  int64_t next() {
    --left;
    if (first) {
      first = false;
      return static_cast<int64_t>(static_cast<uint64_t>(offset) + static_cast<uint64_t>(iv));
    }
    iv = static_cast<int64_t>(static_cast<uint64_t>(iv) + static_cast<uint64_t>(add));
    add = static_cast<int64_t>(static_cast<uint64_t>(add) + static_cast<uint64_t>(add2));
    return iv;
  }
};

// One axis's clock: whole ticks and 1/2^32 ticks.
struct AxisClock {
  uint64_t base = 0;
  uint32_t frac = 0;
  // Advances by one interval (>= 0) and returns the tick of the step.
  uint64_t advance(int64_t interval) {
    const uint64_t acc = static_cast<uint64_t>(frac) + static_cast<uint64_t>(interval);
    base += acc >> kFracBits;
    frac = static_cast<uint32_t>(acc & 0xffffffffu);
    return base;
  }
};

inline size_t put_varint(uint64_t v, uint8_t* out) {
  size_t n = 0;
  do {
    const uint8_t b = v & 0x7f;
    v >>= 7;
    out[n++] = v ? static_cast<uint8_t>(b | 0x80) : b;
  } while (v);
  return n;
}
inline bool get_varint(const uint8_t* d, size_t len, size_t& pos, uint64_t& v) {
  v = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    if (pos >= len) return false;
    const uint8_t b = d[pos++];
    v |= static_cast<uint64_t>(b & 0x7f) << shift;
    if (!(b & 0x80)) return shift < 63 || (b & 0x7e) == 0;
  }
  return false;
}
inline uint64_t zigzag(int64_t v) { return (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63); }
inline int64_t unzigzag(uint64_t v) { return static_cast<int64_t>(v >> 1) ^ -static_cast<int64_t>(v & 1); }

// Even shift (at most 30) of the trailing zero bits of a difference: the wire sends it shifted right by that.
inline int wire_shift(uint64_t d) {
  int s = 0;
  while (d != 0 && s < 30 && (d & ((uint64_t{1} << (s + 2)) - 1)) == 0) s += 2;
  return s;
}

// Items inside QUEUE payloads:
//   tag:   bit 0 axis, bits 1-2 kind (0 run, 1 wait, 2 end, 3 tool), bit 3 direction + or tool down
//          (bits 4-7 zero; a tool item's bit 0 is zero)
//   run:   tag | varint n | s_O/2 + 16 s_I/2 | s_A/2 + 16 s_B/2 |
//          zz(O >> s_O) | zz((I - I') >> s_I) | zz((A - A') >> s_A) | zz((B - B') >> s_B)
//   wait:  tag | varint ticks
//   end:   tag
//   tool:  tag | varint tick
// (I', A', B') is the axis's prediction (continuation() of its previous run; zero before the first). Encoder and
// decoder keep the same predictions, so they must see the same items in the same order.
struct ItemCodec {
  RunRef ref[2];
  // Writes a valid item into out (room for kMaxItemBytes) and returns its size.
  size_t encode(const QueueItem& it, uint8_t* out) {
    const int a = it.kind == ItemKind::tool ? 0 : it.axis & 1;
    size_t n = 0;
    out[n++] = static_cast<uint8_t>(a | (static_cast<int>(it.kind) << 1) | (it.dir > 0 ? 8 : 0));
    if (it.kind == ItemKind::run) {
      const uint64_t d[4] = {static_cast<uint64_t>(it.offset),
                             static_cast<uint64_t>(it.interval) - static_cast<uint64_t>(ref[a].interval),
                             static_cast<uint64_t>(it.add) - static_cast<uint64_t>(ref[a].add),
                             static_cast<uint64_t>(it.add2) - static_cast<uint64_t>(ref[a].add2)};
      int s[4];
      for (int i = 0; i < 4; ++i) s[i] = wire_shift(d[i]);
      n += put_varint(it.count, out + n);
      out[n++] = static_cast<uint8_t>((s[0] / 2) | ((s[1] / 2) << 4));
      out[n++] = static_cast<uint8_t>((s[2] / 2) | ((s[3] / 2) << 4));
      for (int i = 0; i < 4; ++i) n += put_varint(zigzag(static_cast<int64_t>(d[i]) >> s[i]), out + n);
      ref[a] = continuation(it);
    } else if (it.kind == ItemKind::wait || it.kind == ItemKind::tool) {
      n += put_varint(it.wait, out + n);
    }
    return n;
  }
  // Decodes one item at `pos`; false (state and pos unchanged) when the bytes are malformed or the run invalid.
  bool decode(const uint8_t* d, size_t len, size_t& pos, QueueItem& it) {
    size_t p = pos;
    QueueItem r;
    if (!parse(d, len, p, r) || !run_is_valid(r)) return false;
    take(r);
    it = r;
    pos = p;
    return true;
  }
  // decode() in two steps, for a small stack (the firmware's): the item's bytes at `pos` (pos advanced; false
  // when malformed), not checked and not taken; then take() of the item once run_is_valid() accepts it.
  bool parse(const uint8_t* d, size_t len, size_t& pos, QueueItem& r) const {
    size_t p = pos;
    if (p >= len) return false;
    const uint8_t tag = d[p++];
    if (tag & 0xf0) return false;
    const int kind = (tag >> 1) & 3;
    if (kind == static_cast<int>(ItemKind::tool) && (tag & 1)) return false;
    r = QueueItem{};
    r.axis = tag & 1;
    r.kind = static_cast<ItemKind>(kind);
    r.dir = (tag & 8) ? 1 : -1;
    const int a = r.axis;
    if (r.kind == ItemKind::run) {
      uint64_t c;
      if (!get_varint(d, len, p, c) || c == 0 || c > kMaxRunCount || p + 2 > len) return false;
      const uint8_t shifts[2] = {d[p], d[p + 1]};
      p += 2;
      int64_t v[4];
      for (int i = 0; i < 4; ++i) {
        const int s = 2 * ((shifts[i / 2] >> (4 * (i % 2))) & 15);
        uint64_t z;
        if (s > 30 || !get_varint(d, len, p, z)) return false;
        v[i] = static_cast<int64_t>(static_cast<uint64_t>(unzigzag(z)) << s);
      }
      r.count = static_cast<uint32_t>(c);
      r.offset = v[0];
      r.interval = static_cast<int64_t>(static_cast<uint64_t>(ref[a].interval) + static_cast<uint64_t>(v[1]));
      r.add = static_cast<int64_t>(static_cast<uint64_t>(ref[a].add) + static_cast<uint64_t>(v[2]));
      r.add2 = static_cast<int64_t>(static_cast<uint64_t>(ref[a].add2) + static_cast<uint64_t>(v[3]));
    } else if (r.kind == ItemKind::wait || r.kind == ItemKind::tool) {
      if (!get_varint(d, len, p, r.wait)) return false;
    }
    pos = p;
    return true;
  }
  void take(const QueueItem& r) {
    if (r.kind == ItemKind::run) ref[r.axis & 1] = continuation(r);
  }
};

}  // namespace wire
}  // namespace polarcam
