#include "machine/link/protocol.hpp"

#include <zlib.h>

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

static uint32_t crc(const char* p, size_t n) {
  return static_cast<uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(p), static_cast<uInt>(n)));
}

std::string encode_frame(uint16_t seq, uint8_t type, const std::string& payload) {
  std::string f;
  f.reserve(payload.size() + kOverhead);
  f.push_back(static_cast<char>(kSync));
  f.push_back(static_cast<char>(payload.size() + 3));
  f.push_back(static_cast<char>(~(payload.size() + 3) & 0xff));
  f.push_back(static_cast<char>(seq & 0xff));
  f.push_back(static_cast<char>(seq >> 8));
  f.push_back(static_cast<char>(type));
  f += payload;
  uint32_t c = crc(f.data() + 1, f.size() - 1);
  for (int i = 0; i < 4; ++i) f.push_back(static_cast<char>((c >> (8 * i)) & 0xff));
  return f;
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
    const size_t len = static_cast<uint8_t>(buf_[pos + 1]);
    if (len < 3 || len > kMaxPayload + 3 || static_cast<uint8_t>(buf_[pos + 2]) != static_cast<uint8_t>(~len & 0xff)) {
      // not a frame start (or a damaged length)
      ++pos;
      ++skipped_;
      continue;
    }
    const size_t total = 3 + len + 4;
    if (buf_.size() - pos < total) break;
    const char* f = buf_.data() + pos;
    uint32_t stored = 0;
    for (int i = 0; i < 4; ++i) stored |= static_cast<uint32_t>(static_cast<uint8_t>(f[3 + len + i])) << (8 * i);
    if (stored != crc(f + 1, 2 + len)) {
      ++bad_;
      ++pos;  // rescan from the next byte: a frame may start inside the damaged one
      ++skipped_;
      continue;
    }
    Frame fr;
    fr.seq = static_cast<uint16_t>(static_cast<uint8_t>(f[3]) | (static_cast<uint8_t>(f[4]) << 8));
    fr.type = static_cast<uint8_t>(f[5]);
    fr.payload.assign(f + 6, len - 3);
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

std::string Ident::encode() const { return Writer().u8(version).u64(tick_ps).u32(slots).u32(session).str(name).s; }
bool Ident::decode(const std::string& p, Ident& o) {
  Reader r{p};
  o.version = r.u8();
  o.tick_ps = r.u64();
  o.slots = r.u32();
  o.session = r.u32();
  o.name = r.str();
  return r.done();
}

std::string Configure::encode() const {
  return Writer().u64(tick_ps).u8(axes).u64(ramp_ticks).i64(start[0]).i64(start[1]).f64(dr).f64(dtheta).s;
}
bool Configure::decode(const std::string& p, Configure& o) {
  Reader r{p};
  o.tick_ps = r.u64();
  o.axes = r.u8();
  o.ramp_ticks = r.u64();
  o.start[0] = r.i64();
  o.start[1] = r.i64();
  o.dr = r.f64();
  o.dtheta = r.f64();
  return r.done();
}

std::string Ack::encode() const { return Writer().u16(next_seq).u32(free_slots).u8(state).s; }
bool Ack::decode(const std::string& p, Ack& o) {
  Reader r{p};
  o.next_seq = r.u16();
  o.free_slots = r.u32();
  o.state = r.u8();
  return r.done();
}

std::string Status::encode() const {
  return Writer()
      .u8(static_cast<uint8_t>(state)).u8(static_cast<uint8_t>(error)).u32(underruns).u64(now_ticks)
      .u64(schedule_ticks).u32(free_slots).u32(queued).u64(executed[0]).u64(executed[1]).i64(node[0]).i64(node[1])
      .u16(next_seq).u32(session).u32(bad_frames).s;
}
bool Status::decode(const std::string& p, Status& o) {
  Reader r{p};
  uint8_t st = r.u8(), er = r.u8();
  if (st > static_cast<uint8_t>(State::fault)) return false;
  o.state = static_cast<State>(st);
  o.error = static_cast<ErrorCode>(er);
  o.underruns = r.u32();
  o.now_ticks = r.u64();
  o.schedule_ticks = r.u64();
  o.free_slots = r.u32();
  o.queued = r.u32();
  o.executed[0] = r.u64();
  o.executed[1] = r.u64();
  o.node[0] = r.i64();
  o.node[1] = r.i64();
  o.next_seq = r.u16();
  o.session = r.u32();
  o.bad_frames = r.u32();
  return r.done();
}

std::string ErrorMsg::encode() const { return Writer().u8(static_cast<uint8_t>(code)).str(text).s; }
bool ErrorMsg::decode(const std::string& p, ErrorMsg& o) {
  Reader r{p};
  o.code = static_cast<ErrorCode>(r.u8());
  o.text = r.str();
  return r.done();
}

}  // namespace polarcam::proto
