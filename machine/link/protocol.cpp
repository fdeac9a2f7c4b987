#include "machine/link/protocol.hpp"

#include <algorithm>
#include <cstring>

namespace polarcam::proto {

const char* type_name(uint8_t t) {
  switch (t) {
    case IDENTIFY: return "IDENTIFY";
    case CONFIGURE: return "CONFIGURE";
    case QUEUE: return "QUEUE";
    case START: return "START";
    case HOLD: return "HOLD";
    case RESUME: return "RESUME";
    case ABORT: return "ABORT";
    case RESET: return "RESET";
    case STATUS: return "STATUS";
    case ACK: return "ACK";
    case NAK: return "NAK";
    case IDENT: return "IDENT";
    case STATUS_REPLY: return "STATUS_REPLY";
    case ERROR: return "ERROR";
    case BOOT: return "BOOT";
    default: return "unknown";
  }
}

const char* state_name(State s) {
  static const char* names[] = {"idle", "ready", "running", "holding", "held", "resuming", "stopping",
                                "underrun", "done", "aborted", "fault"};
  auto i = static_cast<size_t>(s);
  return i < sizeof names / sizeof *names ? names[i] : "unknown";
}

namespace {
const uint8_t* bytes(const std::string& s) { return reinterpret_cast<const uint8_t*>(s.data()); }
std::string as_string(const uint8_t* p, size_t n) { return std::string(reinterpret_cast<const char*>(p), n); }
uint64_t bits(double v) {
  uint64_t b;
  std::memcpy(&b, &v, 8);
  return b;
}
double from_bits(uint64_t b) {
  double v;
  std::memcpy(&v, &b, 8);
  return v;
}
}  // namespace

std::string encode_frame(uint16_t seq, uint8_t type, const std::string& payload) {
  uint8_t f[wire::kMaxFrame];
  const size_t n = std::min(payload.size(), kMaxPayload);
  return as_string(f, wire::frame_encode(f, seq, type, bytes(payload), n));
}

void FrameDecoder::feed(const uint8_t* data, size_t n, std::vector<Frame>& out) {
  buf_.append(reinterpret_cast<const char*>(data), n);
  size_t pos = 0;
  for (;;) {
    // find sync
    while (pos < buf_.size() && static_cast<uint8_t>(buf_[pos]) != kSync) {
      ++pos;
      ++skipped_;
    }
    if (buf_.size() - pos < 3) break;
    const uint8_t* f = bytes(buf_) + pos;
    if (!wire::frame_len_ok(f[1], f[2])) {  // not a frame start (or a damaged length)
      ++pos;
      ++skipped_;
      continue;
    }
    const size_t total = wire::frame_size(f[1]);
    if (buf_.size() - pos < total) break;
    if (!wire::frame_crc_ok(f)) {
      ++bad_;
      ++pos;  // rescan from the next byte: a frame may start inside the damaged one
      ++skipped_;
      continue;
    }
    Frame fr;
    fr.seq = wire::frame_seq(f);
    fr.type = wire::frame_type(f);
    fr.payload = as_string(wire::frame_payload(f), wire::frame_payload_size(f));
    out.push_back(std::move(fr));
    pos += total;
  }
  buf_.erase(0, pos);
  if (buf_.size() > 4 * (kMaxPayload + kOverhead)) {  // cannot happen with a valid LEN; bound memory anyway
    skipped_ += buf_.size();
    buf_.clear();
  }
}

Writer& Writer::f64(double v) {
  uint64_t b;
  std::memcpy(&b, &v, 8);
  return u64(b);
}
Writer& Writer::str(const std::string& v) {
  const size_t n = v.size() > 200 ? 200 : v.size();
  u8(static_cast<uint8_t>(n));
  s.append(v, 0, n);
  return *this;
}
uint64_t Reader::raw(int n) {
  if (!ok || pos + static_cast<size_t>(n) > s.size()) {
    ok = false;
    return 0;
  }
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(static_cast<uint8_t>(s[pos + i])) << (8 * i);
  pos += static_cast<size_t>(n);
  return v;
}
double Reader::f64() {
  uint64_t b = u64();
  double v;
  std::memcpy(&v, &b, 8);
  return v;
}
std::string Reader::str() {
  size_t n = u8();
  if (!ok || pos + n > s.size()) {
    ok = false;
    return {};
  }
  std::string r = s.substr(pos, n);
  pos += n;
  return r;
}

std::string Ident::encode() const {
  wire::Ident w;
  w.version = version;
  w.tick_ps = tick_ps;
  w.slots = slots;
  w.session = session;
  w.max_step_rate = max_step_rate;
  w.caps = caps;
  w.name = name.data();
  w.name_len = name.size();
  uint8_t b[wire::kMaxPayload];
  return as_string(b, w.encode(b, sizeof b));
}
bool Ident::decode(const std::string& p, Ident& o) {
  wire::Ident w;
  const bool ok = w.decode(bytes(p), p.size());
  o.version = w.version;
  if (!ok) return false;
  o.tick_ps = w.tick_ps;
  o.slots = w.slots;
  o.session = w.session;
  o.max_step_rate = w.max_step_rate;
  o.caps = w.caps;
  o.name.assign(w.name, w.name_len);
  return true;
}

std::string Configure::encode() const {
  wire::Configure w;
  w.tick_ps = tick_ps;
  w.axes = axes;
  w.ramp_ticks = ramp_ticks;
  w.start[0] = start[0];
  w.start[1] = start[1];
  w.dr_bits = bits(dr);
  w.dtheta_bits = bits(dtheta);
  uint8_t b[wire::Configure::kSize];
  return as_string(b, w.encode(b, sizeof b));
}
bool Configure::decode(const std::string& p, Configure& o) {
  wire::Configure w;
  if (!w.decode(bytes(p), p.size())) return false;
  o.tick_ps = w.tick_ps;
  o.axes = w.axes;
  o.ramp_ticks = w.ramp_ticks;
  o.start[0] = w.start[0];
  o.start[1] = w.start[1];
  o.dr = from_bits(w.dr_bits);
  o.dtheta = from_bits(w.dtheta_bits);
  return true;
}

std::string Ack::encode() const {
  wire::Ack w;
  w.next_seq = next_seq;
  w.free_slots = free_slots;
  w.state = state;
  w.free_bytes = free_bytes;
  uint8_t b[wire::Ack::kSize];
  return as_string(b, w.encode(b, sizeof b));
}
bool Ack::decode(const std::string& p, Ack& o) {
  wire::Ack w;
  if (!w.decode(bytes(p), p.size())) return false;
  o.next_seq = w.next_seq;
  o.free_slots = w.free_slots;
  o.state = w.state;
  o.free_bytes = w.free_bytes;
  return true;
}

std::string Status::encode() const {
  uint8_t b[wire::Status::kSize];
  return as_string(b, wire::Status::encode(b, sizeof b));
}
bool Status::decode(const std::string& p, Status& o) { return o.wire::Status::decode(bytes(p), p.size()); }

std::string ErrorMsg::encode() const {
  uint8_t b[wire::kMaxPayload];
  return as_string(b, wire::encode_error(b, sizeof b, code, text.data(), text.size()));
}
bool ErrorMsg::decode(const std::string& p, ErrorMsg& o) {
  wire::Get r(bytes(p), p.size());
  o.code = static_cast<ErrorCode>(r.u8());
  size_t n = 0;
  const char* t = r.str(n);
  o.text.assign(t, n);
  return r.done();
}

}  // namespace polarcam::proto
