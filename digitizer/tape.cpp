#include "digitizer/tape.hpp"
#include "digitizer/tape_file.hpp"

#include <sys/stat.h>
#include <unistd.h>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include <cmath>
#include <numbers>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/input_file.hpp"
#include "digitizer/grid.hpp"
#include "digitizer/speed_profile.hpp"

namespace polarcam {

const char* to_string(TapeRule r) {
  switch (r) {
    case TapeRule::nearest: return "nearest";
    case TapeRule::thesis: return "thesis";
    case TapeRule::dda: return "dda";
    case TapeRule::exact_cartesian: return "exact";
    case TapeRule::capture: return "capture";
  }
  return "unknown";
}

namespace {

constexpr char kMagic[8] = {'P', 'O', 'L', 'A', 'R', 'C', 'A', 'M'};
constexpr size_t kBuf = 1 << 20;
constexpr uint32_t kMaxProvenance = 16u << 20;

// little-endian field codec over a byte array
struct Put {
  uint8_t* p;
  void u8(size_t off, uint8_t v) { p[off] = v; }
  void u16(size_t off, uint16_t v) {
    for (int i = 0; i < 2; ++i) p[off + i] = static_cast<uint8_t>(v >> (8 * i));
  }
  void u32(size_t off, uint32_t v) {
    for (int i = 0; i < 4; ++i) p[off + i] = static_cast<uint8_t>(v >> (8 * i));
  }
  void u64(size_t off, uint64_t v) {
    for (int i = 0; i < 8; ++i) p[off + i] = static_cast<uint8_t>(v >> (8 * i));
  }
  void i64(size_t off, int64_t v) { u64(off, static_cast<uint64_t>(v)); }
  void f64(size_t off, double v) {
    uint64_t b;
    std::memcpy(&b, &v, 8);
    u64(off, b);
  }
};
struct Get {
  const uint8_t* p;
  uint8_t u8(size_t off) const { return p[off]; }
  uint16_t u16(size_t off) const { return static_cast<uint16_t>(p[off] | (p[off + 1] << 8)); }
  uint32_t u32(size_t off) const {
    uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | p[off + i];
    return v;
  }
  uint64_t u64(size_t off) const {
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[off + i];
    return v;
  }
  int64_t i64(size_t off) const { return static_cast<int64_t>(u64(off)); }
  double f64(size_t off) const {
    uint64_t b = u64(off);
    double v;
    std::memcpy(&v, &b, 8);
    return v;
  }
};

// Field offsets of the fixed header (docs/tape-format.md).
enum : size_t {
  kOffMagic = 0, kOffVersion = 8, kOffFixed = 10, kOffProvLen = 12, kOffAxes = 16, kOffRule = 17, kOffFlags = 18,
  kOffTick = 24, kOffRes0 = 32, kOffRes1 = 40, kOffSpr = 48, kOffRmin = 56, kOffRmax = 64, kOffThmin = 72,
  kOffThmax = 80, kOffHome0 = 88, kOffHome1 = 96, kOffStart0 = 104, kOffStart1 = 112, kOffEnd0 = 120,
  kOffEnd1 = 128, kOffCount = 136, kOffPlus0 = 144, kOffMinus0 = 152, kOffPlus1 = 160, kOffMinus1 = 168,
  kOffDuration = 176, kOffLastStep = 184, kOffRecBytes = 192, kOffSpeed = 200, kOffLength = 208,
  kOffRecCrc = 216, kOffHdrCrc = 220, kOffEvents = 224
};
enum : uint16_t { kFlagClosed = 1, kFlagRmax = 2, kFlagTheta = 4, kFlagReturns = 8, kFlagToolUp = 16 };
// A tool event's prefix (version 2): an overlong varint of zero, which no step record is written as.
constexpr uint8_t kEventPrefix[2] = {0x80, 0x00};

std::vector<uint8_t> encode_header(const TapeHeader& h) {
  std::vector<uint8_t> b(kTapeFixedHeader + h.provenance.size(), 0);
  Put w{b.data()};
  std::memcpy(b.data(), kMagic, 8);
  w.u16(kOffVersion, h.version);
  w.u16(kOffFixed, static_cast<uint16_t>(kTapeFixedHeader));
  w.u32(kOffProvLen, static_cast<uint32_t>(h.provenance.size()));
  w.u8(kOffAxes, static_cast<uint8_t>(h.axes));
  w.u8(kOffRule, static_cast<uint8_t>(h.rule));
  uint16_t flags = (h.closed ? kFlagClosed : 0) | (h.has_r_max ? kFlagRmax : 0) | (h.has_theta_range ? kFlagTheta : 0) |
                   (h.returns_to_start ? kFlagReturns : 0);
  if (h.version >= kTapeVersionEvents && h.tool_starts_up) flags |= kFlagToolUp;
  w.u16(kOffFlags, flags);
  w.u64(kOffTick, h.tick_ps);
  w.f64(kOffRes0, h.res[0]);
  w.f64(kOffRes1, h.res[1]);
  w.i64(kOffSpr, h.steps_per_rev);
  w.f64(kOffRmin, h.r_min);
  w.f64(kOffRmax, h.has_r_max ? h.r_max : 0.0);
  w.f64(kOffThmin, h.has_theta_range ? h.theta_min : 0.0);
  w.f64(kOffThmax, h.has_theta_range ? h.theta_max : 0.0);
  w.i64(kOffHome0, h.home[0]);
  w.i64(kOffHome1, h.home[1]);
  w.i64(kOffStart0, h.start[0]);
  w.i64(kOffStart1, h.start[1]);
  w.i64(kOffEnd0, h.end[0]);
  w.i64(kOffEnd1, h.end[1]);
  w.u64(kOffCount, h.record_count);
  w.u64(kOffPlus0, h.plus[0]);
  w.u64(kOffMinus0, h.minus[0]);
  w.u64(kOffPlus1, h.plus[1]);
  w.u64(kOffMinus1, h.minus[1]);
  w.u64(kOffDuration, h.duration_ticks);
  w.u64(kOffLastStep, h.last_step_ticks);
  w.u64(kOffRecBytes, h.records_bytes);
  w.f64(kOffSpeed, h.speed_mps);
  w.f64(kOffLength, h.path_length_m);
  w.u32(kOffRecCrc, h.records_crc);
  if (h.version >= kTapeVersionEvents) w.u64(kOffEvents, h.event_count);
  std::memcpy(b.data() + kTapeFixedHeader, h.provenance.data(), h.provenance.size());
  uint32_t hc = static_cast<uint32_t>(crc32(0L, b.data(), static_cast<uInt>(b.size())));
  w.u32(kOffHdrCrc, hc);
  return b;
}

}  // namespace

// ------------------------------------------------------------------------------------------------ writer

TapeWriter::TapeWriter(const std::string& path, const TapeHeader& h) : path_(path) {
  if (h.provenance.size() > kMaxProvenance) throw InputError("the provenance block is too large", path);
  out_ = std::make_unique<OutputFile>(path);
  f_ = out_->stream();
  header_size_ = kTapeFixedHeader + h.provenance.size();
  std::vector<uint8_t> zeros(header_size_, 0);
  if (std::fwrite(zeros.data(), 1, zeros.size(), f_) != zeros.size())
    throw DeviceError(std::string("cannot write (") + std::strerror(errno) + ")", path);
  buf_.reserve(kBuf + 16);
  crc_ = static_cast<uint32_t>(crc32(0L, Z_NULL, 0));
  tool_starts_up_ = h.tool_starts_up;
  tool_down_ = !h.tool_starts_up;
}

TapeWriter::~TapeWriter() = default;  // an unfinished tape's temporary file goes with out_

void TapeWriter::write(const StepRecord& r) {
  if (r.interval >> 62) throw std::length_error("tape interval does not fit 62 bits");
  uint64_t v = (r.interval << 2) | (static_cast<uint64_t>(r.axis & 1) << 1) | (r.dir > 0 ? 1u : 0u);
  do {
    uint8_t byte = v & 0x7f;
    v >>= 7;
    buf_.push_back(v ? (byte | 0x80) : byte);
  } while (v);
  ++count_;
  (r.dir > 0 ? plus_ : minus_)[r.axis & 1] += 1;
  cum_ticks_ += r.interval;
  if (buf_.size() >= kBuf) flush();
}

void TapeWriter::step(int axis, int dir, int64_t t_ns) {
  StepRecord r;
  r.interval = static_cast<uint64_t>(t_ns - last_ns_);
  r.axis = axis;
  r.dir = dir;
  last_ns_ = t_ns;
  write(r);
}

void TapeWriter::tool(bool down, int64_t t_ns) {
  if (down == tool_down_)
    throw std::logic_error(std::string("internal error: the tool is already ") + (down ? "down" : "up"));
  if (t_ns < last_ns_) throw std::logic_error("internal error: a tool event before the previous record");
  const uint64_t interval = static_cast<uint64_t>(t_ns - last_ns_);
  if (interval >> 62) throw std::length_error("tape interval does not fit 62 bits");
  last_ns_ = t_ns;
  buf_.push_back(kEventPrefix[0]);
  buf_.push_back(kEventPrefix[1]);
  uint64_t v = (interval << 2) | (down ? 1u : 0u);
  do {
    uint8_t byte = v & 0x7f;
    v >>= 7;
    buf_.push_back(v ? (byte | 0x80) : byte);
  } while (v);
  tool_down_ = down;
  ++events_;
  cum_ticks_ += interval;
  if (buf_.size() >= kBuf) flush();
}

void TapeWriter::flush() {
  if (buf_.empty()) return;
  crc_ = static_cast<uint32_t>(crc32(crc_, buf_.data(), static_cast<uInt>(buf_.size())));
  if (std::fwrite(buf_.data(), 1, buf_.size(), f_) != buf_.size())
    throw DeviceError(std::string("cannot write (") + std::strerror(errno) + ")", path_);
  bytes_ += buf_.size();
  buf_.clear();
}

void TapeWriter::finish(TapeHeader h) {
  flush();
  h.record_count = count_;
  h.records_bytes = bytes_;
  h.records_crc = crc_;
  h.last_step_ticks = cum_ticks_;
  h.version = events_ > 0 ? kTapeVersionEvents : kTapeVersion;
  h.event_count = events_;
  h.tool_starts_up = events_ > 0 && tool_starts_up_;
  for (int a = 0; a < 2; ++a) {
    h.plus[a] = plus_[a];
    h.minus[a] = minus_[a];
    if (h.end[a] != h.start[a] + static_cast<int64_t>(plus_[a]) - static_cast<int64_t>(minus_[a]))
      throw std::logic_error("internal error: the tape's end node does not match its steps");
  }
  if (h.duration_ticks < h.last_step_ticks) h.duration_ticks = h.last_step_ticks;
  std::vector<uint8_t> hb = encode_header(h);
  if (hb.size() != header_size_) throw std::logic_error("internal error: the provenance changed while writing");
  if (std::fseek(f_, 0, SEEK_SET) != 0 || std::fwrite(hb.data(), 1, hb.size(), f_) != hb.size())
    throw DeviceError(std::string("cannot write (") + std::strerror(errno) + ")", path_);
  out_->commit();
}

// ------------------------------------------------------------------------------------------------ reader

TapeReader::TapeReader(const std::string& path) : path_(path) {
  refuse_directory(path);
  f_ = std::fopen(path.c_str(), "rb");
  if (!f_) throw InputError(std::string("cannot open the tape (") + std::strerror(errno) + ")", path);
  // The destructor does not run when the constructor throws: a tape refused here closes its file here.
  struct CloseUnlessAccepted {
    std::FILE*& f;
    bool accepted = false;
    ~CloseUnlessAccepted() {
      if (!accepted) {
        std::fclose(f);
        f = nullptr;
      }
    }
  } close_unless_accepted{f_};
  std::vector<uint8_t> fixed(kTapeFixedHeader);
  size_t got = std::fread(fixed.data(), 1, fixed.size(), f_);
  if (got < 8 || std::memcmp(fixed.data(), kMagic, 8) != 0) fail("not a polarcam tape (bad magic)");
  if (got < 16) fail("the header is truncated");
  Get g{fixed.data()};
  h_.version = g.u16(kOffVersion);
  if (h_.version != kTapeVersion && h_.version != kTapeVersionEvents)
    fail("tape format version " + std::to_string(h_.version) + " is not supported (this polarcam reads versions " +
         std::to_string(kTapeVersion) + " and " + std::to_string(kTapeVersionEvents) + ")");
  if (got < kTapeFixedHeader) fail("the header is truncated");
  if (g.u16(kOffFixed) != kTapeFixedHeader) fail("the header size is wrong");
  uint32_t plen = g.u32(kOffProvLen);
  if (plen > kMaxProvenance) fail("the provenance block is too large");
  std::vector<uint8_t> all(kTapeFixedHeader + plen);
  std::memcpy(all.data(), fixed.data(), kTapeFixedHeader);
  if (std::fread(all.data() + kTapeFixedHeader, 1, plen, f_) != plen) fail("the header is truncated");
  uint32_t stored = Get{all.data()}.u32(kOffHdrCrc);
  Put{all.data()}.u32(kOffHdrCrc, 0);
  uint32_t calc = static_cast<uint32_t>(crc32(0L, all.data(), static_cast<uInt>(all.size())));
  if (stored != calc) fail("the header checksum does not match (the header is corrupted)");
  g = Get{all.data()};
  uint8_t axes = g.u8(kOffAxes), rule = g.u8(kOffRule);
  if (axes > 1) fail("unknown axis kind " + std::to_string(axes));
  if (rule > 4) fail("unknown stepping rule " + std::to_string(rule));
  h_.axes = static_cast<TapeAxes>(axes);
  h_.rule = static_cast<TapeRule>(rule);
  uint16_t flags = g.u16(kOffFlags);
  const uint16_t known = kFlagClosed | kFlagRmax | kFlagTheta | kFlagReturns |
                         (h_.version >= kTapeVersionEvents ? kFlagToolUp : 0);
  if (flags & ~known)
    fail("the header's flags have bits this tape format version does not define (" + std::to_string(flags & ~known) +
         ")");
  h_.closed = flags & kFlagClosed;
  h_.has_r_max = flags & kFlagRmax;
  h_.has_theta_range = flags & kFlagTheta;
  h_.returns_to_start = flags & kFlagReturns;
  if (h_.version >= kTapeVersionEvents) {
    h_.tool_starts_up = flags & kFlagToolUp;
    h_.event_count = g.u64(kOffEvents);
  }
  tool_down_ = !h_.tool_starts_up;
  h_.tick_ps = g.u64(kOffTick);
  h_.res[0] = g.f64(kOffRes0);
  h_.res[1] = g.f64(kOffRes1);
  h_.steps_per_rev = g.i64(kOffSpr);
  h_.r_min = g.f64(kOffRmin);
  h_.r_max = g.f64(kOffRmax);
  h_.theta_min = g.f64(kOffThmin);
  h_.theta_max = g.f64(kOffThmax);
  h_.home[0] = g.i64(kOffHome0);
  h_.home[1] = g.i64(kOffHome1);
  h_.start[0] = g.i64(kOffStart0);
  h_.start[1] = g.i64(kOffStart1);
  h_.end[0] = g.i64(kOffEnd0);
  h_.end[1] = g.i64(kOffEnd1);
  h_.record_count = g.u64(kOffCount);
  h_.plus[0] = g.u64(kOffPlus0);
  h_.minus[0] = g.u64(kOffMinus0);
  h_.plus[1] = g.u64(kOffPlus1);
  h_.minus[1] = g.u64(kOffMinus1);
  h_.duration_ticks = g.u64(kOffDuration);
  h_.last_step_ticks = g.u64(kOffLastStep);
  h_.records_bytes = g.u64(kOffRecBytes);
  h_.speed_mps = g.f64(kOffSpeed);
  h_.path_length_m = g.f64(kOffLength);
  h_.records_crc = g.u32(kOffRecCrc);
  h_.header_crc = stored;
  h_.provenance.assign(reinterpret_cast<const char*>(all.data() + kTapeFixedHeader), plen);
  validate_header();
  max_ticks_ = max_time_ticks();
  struct stat st;  // the read buffer no larger than the records (a small tape does not take a megabyte)
  const bool sized = ::fstat(::fileno(f_), &st) == 0 && st.st_size >= 0;
  buf_.resize(sized ? std::min<size_t>(kBuf, static_cast<size_t>(st.st_size) + 1) : kBuf);
  crc_ = static_cast<uint32_t>(crc32(0L, Z_NULL, 0));
  close_unless_accepted.accepted = true;
}

// A tape that passes its checksums may still be hostile (or written by another program): every header field is
// checked against what the later arithmetic can hold, the same bounds the digitizer keeps (digitizer/grid.hpp,
// digitizer/speed_profile.hpp): node indices within 2^50, times within 2^62 ns, resolutions no finer than a tape
// holds.
constexpr int64_t kMaxNode = int64_t{1} << 50;

void TapeReader::validate_header() const {
  const bool polar = h_.axes == TapeAxes::polar;
  for (int a = 0; a < 2; ++a) {
    const double finest = (polar && a == 1) ? 2.0 * std::numbers::pi / static_cast<double>(kMaxStepsPerRev)
                                            : kMinRadialResolution;
    if (!(h_.res[a] >= finest) || !std::isfinite(h_.res[a]))
      fail("the header's resolution of axis " + std::to_string(a) + " (" + significant(h_.res[a]) +
           ") is not a finite positive number at least " + significant(finest));
  }
  if (h_.tick_ps == 0 || h_.tick_ps > 1000000000000ULL) fail("the header's tick is not from 1 ps to 1 s");
  if (h_.steps_per_rev < 0 || h_.steps_per_rev > kMaxStepsPerRev)
    fail("the header's steps per revolution (" + std::to_string(h_.steps_per_rev) + ") is not from 0 to 2^40");
  if (!std::isfinite(h_.r_min) || (polar && h_.r_min < 0))
    fail("the header's r_min (" + significant(h_.r_min) + ") is not a finite length of zero or more");
  if (h_.has_r_max && (!std::isfinite(h_.r_max) || !(h_.r_max > h_.r_min)))
    fail("the header's r_max (" + significant(h_.r_max) + ") is not a finite length above r_min");
  if (h_.has_theta_range &&
      (!std::isfinite(h_.theta_min) || !std::isfinite(h_.theta_max) || !(h_.theta_max > h_.theta_min)))
    fail("the header's angular range (" + significant(h_.theta_min) + " to " + significant(h_.theta_max) +
         " rad) is not finite and increasing");
  if (!std::isfinite(h_.speed_mps) || h_.speed_mps < 0 || !std::isfinite(h_.path_length_m) || h_.path_length_m < 0)
    fail("the header's speed or path length is not a finite number of zero or more");
  const auto node_ok = [](int64_t v) { return v >= -kMaxNode && v <= kMaxNode; };
  const char* name[2] = {polar ? "radial" : "x", polar ? "angular" : "y"};
  for (int a = 0; a < 2; ++a) {
    if (!node_ok(h_.home[a]) || !node_ok(h_.start[a]) || !node_ok(h_.end[a]))
      fail(std::string("the header's ") + name[a] + " home, start or end node lies beyond 2^50 steps from node 0");
    if (h_.plus[a] > static_cast<uint64_t>(kMaxNode) || h_.minus[a] > static_cast<uint64_t>(kMaxNode))
      fail(std::string("the header's ") + name[a] + " step counts exceed 2^50");
    if (h_.start[a] + static_cast<int64_t>(h_.plus[a]) - static_cast<int64_t>(h_.minus[a]) != h_.end[a])
      fail(std::string("the header's ") + name[a] + " end node is not its start node plus its steps");
  }
  if (h_.plus[0] + h_.minus[0] + h_.plus[1] + h_.minus[1] != h_.record_count)
    fail("the header's step totals do not add up to its record count");
  if (h_.event_count > h_.records_bytes / 3)
    fail("the header's tool event count (" + std::to_string(h_.event_count) + ") does not fit its records' bytes");
  const uint64_t max_ticks = max_time_ticks();
  if (h_.duration_ticks > max_ticks || h_.last_step_ticks > max_ticks)
    fail("the header's duration or last step time exceeds 2^62 ns (about 146 years)");
  if (h_.duration_ticks < h_.last_step_ticks) fail("the header's duration is shorter than its last step's time");
}

uint64_t TapeReader::max_time_ticks() const {
  const double ticks = kMaxDurationNs * 1000.0 / static_cast<double>(h_.tick_ps);
  return ticks >= 0x1p63 ? uint64_t{1} << 63 : static_cast<uint64_t>(ticks);
}

TapeReader::~TapeReader() {
  if (f_) std::fclose(f_);
}

void TapeReader::fail(const std::string& what) const { throw InputError(what, path_); }

void TapeReader::ran_out(const std::string& which) const {
  // every byte the header counts is there, yet the records end early: a damaged record, not a short file
  if (bytes_ >= h_.records_bytes && crc_ != h_.records_crc)
    fail(which + " is missing although all " + std::to_string(h_.records_bytes) +
         " bytes of records are there, and their checksum does not match: the tape is corrupted");
  fail(which + " is missing (the tape is truncated)");
}

bool TapeReader::fill() {
  len_ = std::fread(buf_.data(), 1, buf_.size(), f_);
  pos_ = 0;
  if (len_ > 0) {
    crc_ = static_cast<uint32_t>(crc32(crc_, buf_.data(), static_cast<uInt>(len_)));
    bytes_ += len_;
  }
  return len_ > 0;
}

bool TapeReader::next_record(StepRecord& r) {
  if (finished_) return false;
  for (;;) {
    if (n_ == h_.record_count && events_ == h_.event_count) {
      // all records read: nothing may follow, and the totals must agree
      if (pos_ < len_ || fill()) fail("unexpected data after record " + std::to_string(n_));
      if (bytes_ != h_.records_bytes)
        fail("the records take " + std::to_string(bytes_) + " bytes but the header says " + std::to_string(h_.records_bytes));
      if (crc_ != h_.records_crc) fail("the records' checksum does not match (the tape is corrupted)");
      for (int a = 0; a < 2; ++a)
        if (h_.plus[a] != plus_[a] || h_.minus[a] != minus_[a])
          fail("the step counts of axis " + std::to_string(a) + " do not match the header");
      if (cum_ != h_.last_step_ticks) fail("the record intervals do not add up to the header's last step time");
      finished_ = true;
      return false;
    }
    // the record's name for a message, formed only when one is needed
    auto which = [&] {
      return n_ < h_.record_count ? "record " + std::to_string(n_ + 1) : "tool event " + std::to_string(events_ + 1);
    };
    uint64_t v = 0;
    int shift = 0, nbytes = 0;
    uint8_t b = 0;
    for (;;) {
      if (pos_ == len_ && !fill())
        ran_out(h_.event_count == 0 ? which() + " of " + std::to_string(h_.record_count)
                                    : which() + " of " + std::to_string(h_.record_count) + " steps and " +
                                          std::to_string(h_.event_count) + " tool events");
      b = buf_[pos_++];
      ++nbytes;
      if (shift == 63 && (b & 0x7e)) fail(which() + " is malformed (varint overflow)");
      v |= static_cast<uint64_t>(b & 0x7f) << shift;
      if (!(b & 0x80)) break;
      shift += 7;
      if (shift > 63) fail(which() + " is malformed (varint too long)");
    }
    if (h_.version >= kTapeVersionEvents && nbytes > 1 && b == 0) {
      // version 2: 0x80 0x00 announces a tool event; no other overlong varint is written
      if (nbytes != 2) fail(which() + " is malformed (an overlong varint)");
      if (events_ == h_.event_count)
        fail("tool event " + std::to_string(events_ + 1) + " is one more than the header's " +
             std::to_string(h_.event_count));
      const std::string ev = "tool event " + std::to_string(events_ + 1) + " (after step " + std::to_string(n_) + ")";
      v = 0;
      shift = 0;
      for (;;) {
        if (pos_ == len_ && !fill()) ran_out(ev);
        b = buf_[pos_++];
        if (shift == 63 && (b & 0x7e)) fail(ev + " is malformed (varint overflow)");
        v |= static_cast<uint64_t>(b & 0x7f) << shift;
        if (!(b & 0x80)) break;
        shift += 7;
        if (shift > 63) fail(ev + " is malformed (varint too long)");
      }
      if (v & 2) fail(ev + " has an unknown code " + std::to_string(v & 3) + " (0 tool up, 1 tool down)");
      const bool down = v & 1;
      if (down == tool_down_)
        fail(ev + " puts the tool " + (down ? "down" : "up") + " where it already is: tool events must alternate");
      const uint64_t interval = v >> 2;
      if (interval > max_time_ticks() - cum_) fail(ev + " takes the tape's time beyond 2^62 ns (about 146 years)");
      cum_ += interval;
      pending_ += interval;
      tool_down_ = down;
      ++events_;
      if (!on_event_)
        fail(ev + ": this reader does not handle tool events (tool up / tool down, tape format version 2)");
      on_event_(ToolEvent{cum_, down, n_});
      continue;
    }
    if (n_ == h_.record_count) fail("record " + std::to_string(n_ + 1) + " is one more than the header's " + std::to_string(h_.record_count));
    if ((v >> 2) > max_ticks_ - cum_)
      fail("record " + std::to_string(n_ + 1) + " takes the tape's time beyond 2^62 ns (about 146 years)");
    accept(r, v);
    return true;
  }
}

TapeHeader verify_tape(const std::string& path) {
  TapeReader rd(path);
  rd.on_tool_event([](const ToolEvent&) {});
  StepRecord r;
  while (rd.next(r)) {
  }
  return rd.header();
}

}  // namespace polarcam

namespace polarcam {

void refuse_tool_events(const TapeHeader& h, const std::string& path, const std::string& what, const std::string& advice) {
  if (h.event_count > 0)
    throw InputError(what + " does not handle tool events (tool up / tool down, " + std::to_string(h.event_count) +
                         " in this tape): " + advice,
                     path);
}

double tape_coupling_steps_per_rev(const TapeHeader& h) {
  const auto prov = nlohmann::json::parse(h.provenance, nullptr, false);
  if (prov.is_discarded() || !prov.is_object() || !prov.contains("job")) return 0.0;
  const auto& job = prov["job"];
  if (!job.is_object() || !job.contains("machine") || !job["machine"].is_object()) return 0.0;
  const auto& m = job["machine"];
  if (!m.contains("coupling_steps_per_rev") || !m["coupling_steps_per_rev"].is_number()) return 0.0;
  const double c = m["coupling_steps_per_rev"].get<double>();
  return std::isfinite(c) ? c : 0.0;
}

bool is_tape_file(const std::string& path) {
  if (path.size() >= 5 && path.compare(path.size() - 5, 5, ".tape") == 0) return true;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  char head[8] = {};
  const bool magic = std::fread(head, 1, 8, f) == 8 && std::memcmp(head, kMagic, 8) == 0;
  std::fclose(f);
  return magic;
}

}  // namespace polarcam
