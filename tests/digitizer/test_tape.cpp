// The step tape: round trip, determinism, and every kind of damage detected.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <fstream>
#include <iterator>
#include <numbers>

#include "cam/curves.hpp"
#include "cam/error.hpp"
#include "digitizer/tape.hpp"
#include "tests/helpers.hpp"
#include "digitizer/replay.hpp"

namespace tu_digitizer_test_tape {  // the test files of a program compile together (unity build)

using namespace polarcam;
using polarcam::test::RecordingSink;
using polarcam::test::temp_path;
using polarcam::test::thesis_grid;

namespace {

struct Written {
  std::vector<polarcam::test::Recorded> steps;
  DigitizeResult r;
};

Written write_limacon(const std::string& path, const std::string& provenance = "{\"test\":1}") {
  auto tp = make_tool_path(make_limacon(0.0508, 0.0762), Placement{0.0127, 0}, ToolSpec{}, TravelSpec{});
  PolarTrack tr = PolarTrack::build(*tp);
  auto prof = make_constant_speed(0.0152, tr.length());
  Grid g = thesis_grid();
  TapeHeader h;
  h.res[0] = g.dr;
  h.res[1] = g.dtheta;
  h.steps_per_rev = g.steps_per_rev;
  h.provenance = provenance;
  struct Tee : StepSink {
    StepSink* a;
    RecordingSink b;
    void step(int axis, int dir, int64_t t) override {
      a->step(axis, dir, t);
      b.step(axis, dir, t);
    }
  } tee;
  TapeWriter w(path, h);
  tee.a = &w;
  Written out;
  out.r = digitize(tr, g, StepRule::nearest, *prof, &tee);
  h.start[0] = out.r.start_n;
  h.start[1] = out.r.start_m;
  h.end[0] = out.r.end_n;
  h.end[1] = out.r.end_m;
  h.duration_ticks = static_cast<uint64_t>(out.r.duration_ns);
  w.finish(h);
  out.steps = tee.b.steps;
  return out;
}

std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
void spit(const std::string& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out << s;
}

}  // namespace

TEST(Tape, ReadsBackExactlyWhatWasWritten) {
  std::string p = temp_path("rt.tape");
  Written w = write_limacon(p);
  TapeReader rd(p);
  EXPECT_EQ(rd.header().record_count, w.steps.size());
  EXPECT_EQ(rd.header().start[0], w.r.start_n);
  EXPECT_EQ(rd.header().end[1], w.r.end_m);
  EXPECT_EQ(rd.header().provenance, "{\"test\":1}");
  TapeReplay rp(rd);
  MachineStep s;
  size_t i = 0;
  int64_t node[2] = {w.r.start_n, w.r.start_m};
  while (rp.next(s)) {
    ASSERT_LT(i, w.steps.size());
    EXPECT_EQ(s.axis, w.steps[i].axis);
    EXPECT_EQ(s.dir, w.steps[i].dir);
    EXPECT_EQ(static_cast<int64_t>(s.t_ticks), w.steps[i].t_ns);
    node[s.axis] += s.dir;
    EXPECT_EQ(s.node[0], node[0]);
    EXPECT_EQ(s.node[1], node[1]);
    ++i;
  }
  EXPECT_EQ(i, w.steps.size());
  std::remove(p.c_str());
}

TEST(Tape, IdenticalJobsGiveIdenticalBytes) {
  std::string a = temp_path("a.tape"), b = temp_path("b.tape");
  write_limacon(a);
  write_limacon(b);
  EXPECT_EQ(slurp(a), slurp(b));
  std::remove(a.c_str());
  std::remove(b.c_str());
}

TEST(Tape, DamageIsDetected) {
  std::string p = temp_path("dmg.tape"), q = temp_path("dmg2.tape");
  write_limacon(p);
  const std::string good = slurp(p);
  auto expect_bad = [&](const std::string& bytes, const char* what) {
    spit(q, bytes);
    EXPECT_THROW(verify_tape(q), InputError) << what;
  };
  std::string s = good;
  s[good.size() / 2] ^= 0x10;
  expect_bad(s, "a flipped bit in the records");
  expect_bad(good.substr(0, good.size() - 3), "a truncated tape");
  // a record byte set to 0xff (its continuation bit set) runs the varints together, so the records end early though
  // every byte is there: called corrupted, not truncated; a short file is still called truncated
  auto message = [&](const std::string& bytes) {
    spit(q, bytes);
    try {
      verify_tape(q);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  s = good;
  s[good.size() / 2] = static_cast<char>(0xff);
  const std::string merged = message(s);
  EXPECT_NE(merged.find("the tape is corrupted"), std::string::npos) << merged;
  EXPECT_EQ(merged.find("truncated"), std::string::npos) << merged;
  const std::string shorter = message(good.substr(0, good.size() - 3));
  EXPECT_NE(shorter.find("the tape is truncated"), std::string::npos) << shorter;
  expect_bad(good + "x", "trailing bytes");
  s = good;
  s[60] ^= 1;
  expect_bad(s, "a flipped bit in the header");
  s = good;
  s[0] = 'X';
  expect_bad(s, "a wrong magic");
  expect_bad(good.substr(0, 100), "a truncated header");
  spit(q, good.substr(0, 8));  // the magic alone: a tape cut short, not another kind of file
  try {
    verify_tape(q);
    ADD_FAILURE() << "accepted the magic alone";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the header is truncated"), std::string::npos) << e.what();
  }
  expect_bad("", "an empty file");
  EXPECT_THROW(verify_tape(temp_path("does-not-exist.tape")), InputError);
  spit(q, good);
  EXPECT_NO_THROW(verify_tape(q));
  std::remove(p.c_str());
  std::remove(q.c_str());
}

TEST(Tape, UnfinishedWriterLeavesNoFile) {
  std::string p = temp_path("unfinished.tape");
  {
    TapeHeader h;
    h.res[0] = 1e-5;
    h.res[1] = 1e-3;
    TapeWriter w(p, h);
    w.step(0, 1, 10);
  }
  std::ifstream in(p);
  EXPECT_FALSE(in.good());
}

TEST(Tape, VarintsCoverTheWholeRange) {
  std::string p = temp_path("range.tape");
  TapeHeader h;
  h.res[0] = 1e-5;
  h.res[1] = 1e-3;
  std::vector<uint64_t> intervals{0, 1, 127, 128, 16383, 16384, (1ull << 40) + 5, (1ull << 61) + 3};
  {
    TapeWriter w(p, h);
    for (uint64_t iv : intervals) w.write(StepRecord{iv, 1, -1});
    h.end[1] = -static_cast<int64_t>(intervals.size());
    h.duration_ticks = 0;
    w.finish(h);
  }
  TapeReader rd(p);
  StepRecord r;
  size_t i = 0;
  while (rd.next(r)) {
    EXPECT_EQ(r.interval, intervals[i]);
    EXPECT_EQ(r.axis, 1);
    EXPECT_EQ(r.dir, -1);
    ++i;
  }
  EXPECT_EQ(i, intervals.size());
  std::remove(p.c_str());
}

namespace {

// CRC-32 (ISO-HDLC, reflected polynomial 0xEDB88320), bit by bit, as docs/tape-format.md specifies it
uint32_t crc32_bits(const std::string& s) {
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : s) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return ~c;
}
template <class T>
void put(std::string& s, size_t off, T v) {
  std::memcpy(&s[off], &v, sizeof v);  // little-endian host, as the tape
}
// The tape with its header checksum recomputed the way the reader checks it (the fixed header and the
// provenance, with the checksum field zeroed).
std::string reseal(std::string s) {
  uint32_t plen = 0;
  std::memcpy(&plen, &s[12], 4);
  put<uint32_t>(s, 220, 0);
  put<uint32_t>(s, 220, crc32_bits(s.substr(0, 256 + plen)));
  return s;
}

}  // namespace

TEST(Tape, HostileHeadersThatPassTheirChecksumsAreRefused) {
  std::string p = temp_path("host.tape"), q = temp_path("host2.tape");
  write_limacon(p);
  const std::string good = slurp(p);
  spit(q, reseal(good));
  ASSERT_NO_THROW(verify_tape(q)) << "resealing an untouched tape must keep it valid";
  auto expect_bad = [&](std::string bytes, const char* mention) {
    spit(q, reseal(std::move(bytes)));
    try {
      verify_tape(q);
      ADD_FAILURE() << "accepted: " << mention;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    }
  };
  const double nan = std::nan("");
  std::string s = good;
  put(s, 56, nan);
  expect_bad(s, "r_min");
  s = good;
  put<uint16_t>(s, 18, static_cast<uint16_t>(s[18] | 2));  // has r_max
  put(s, 64, nan);
  expect_bad(s, "r_max");
  s = good;
  put<int64_t>(s, 48, -16000);
  expect_bad(s, "steps per revolution");
  s = good;
  put(s, 32, 0.0);
  expect_bad(s, "resolution");
  s = good;
  put(s, 40, std::numeric_limits<double>::infinity());
  expect_bad(s, "resolution");
  // the start node at 2^62 (the end node moved with it, so the steps still add up)
  int64_t start = 0, end = 0;
  std::memcpy(&start, &good[104], 8);
  std::memcpy(&end, &good[120], 8);
  s = good;
  put<int64_t>(s, 104, int64_t{1} << 62);
  put<int64_t>(s, 120, (int64_t{1} << 62) + (end - start));
  expect_bad(s, "2^50");
  s = good;
  put<int64_t>(s, 120, end + 1);
  expect_bad(s, "end node");
  // flags this version does not define: bit 4 (the tool's state, version 2 only) and bit 5 in a version 1 tape
  for (uint16_t bit : {uint16_t{16}, uint16_t{32}}) {
    s = good;
    uint16_t flags = 0;
    std::memcpy(&flags, &good[18], 2);
    put<uint16_t>(s, 18, static_cast<uint16_t>(flags | bit));
    expect_bad(s, "flags have bits this tape format version does not define");
  }
  // a duration (offset 176) shorter than the last step's time
  s = good;
  put<uint64_t>(s, 176, 0);
  expect_bad(s, "duration is shorter than its last step's time");
  std::remove(p.c_str());
  std::remove(q.c_str());
}

TEST(Tape, RecordsWhoseTimesPassTwoToTheSixtyTwoNanosecondsAreRefused) {
  std::string p = temp_path("long.tape");
  TapeHeader h;
  h.res[0] = 1e-4;
  h.res[1] = 2 * std::numbers::pi / 1000;
  h.steps_per_rev = 1000;
  h.provenance = "{}";
  {
    TapeWriter w(p, h);
    w.write(StepRecord{(uint64_t{1} << 62) - 1, 1, 1});  // the largest interval a record holds, then one more tick
    w.write(StepRecord{2, 1, 1});
    h.end[1] = 2;
    w.finish(h);
  }
  try {
    verify_tape(p);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2^62"), std::string::npos) << e.what();
  }
  std::remove(p.c_str());
}

// Found by fuzzing (fuzz_tape): a tape refused while its header was read left its file open, one descriptor per
// refused tape, until the process could open no more files. Refuse the same tape more times than a process has
// descriptors by default; the lowest free descriptor afterwards is the one before.
TEST(Tape, RefusedTapesCloseTheirFiles) {
  const std::string p = temp_path("refused.tape");
  spit(p, std::string("POLARCAM") + std::string(300, '\0'));  // the magic, then a header of the wrong version
  auto lowest_free_fd = [] {
    std::FILE* f = std::fopen("/dev/null", "rb");
    if (!f) return -1;  // no descriptor left
    const int fd = fileno(f);
    std::fclose(f);
    return fd;
  };
  const int before = lowest_free_fd();
  for (int i = 0; i < 1100; ++i) EXPECT_THROW(TapeReader r(p), InputError);
  EXPECT_EQ(lowest_free_fd(), before);
  std::remove(p.c_str());
}

// ------------------------------------------------------------------------------------------ tool events (v2)

namespace {

// A small hand-made tape: steps and tool events at the given times (ns); events as axis -1 (dir +1: down, -1: up).
struct Rec {
  int axis, dir;
  int64_t t;
};
void write_small(const std::string& p, const std::vector<Rec>& recs, bool starts_up = false) {
  TapeHeader h;
  h.res[0] = 1e-5;
  h.res[1] = 1e-3;
  h.tool_starts_up = starts_up;
  h.provenance = "{}";
  TapeWriter w(p, h);
  int64_t node[2] = {0, 0};
  for (const Rec& r : recs) {
    if (r.axis < 0) {
      w.tool(r.dir > 0, r.t);
    } else {
      w.step(r.axis, r.dir, r.t);
      node[r.axis] += r.dir;
    }
  }
  h.end[0] = node[0];
  h.end[1] = node[1];
  h.duration_ticks = 1000;
  w.finish(h);
}

// The record section of a tape (after the fixed header and the provenance).
std::string records_of(const std::string& tape) {
  uint32_t plen = 0;
  std::memcpy(&plen, &tape[12], 4);
  return tape.substr(256 + plen);
}

}  // namespace

TEST(TapeEvents, AWriterWithoutEventsWritesVersionOne) {
  const std::string p = temp_path("noev.tape");
  write_small(p, {{0, 1, 10}, {1, -1, 20}}, /*starts_up=*/true);
  const std::string b = slurp(p);
  EXPECT_EQ(static_cast<unsigned char>(b[8]), 1u);
  EXPECT_EQ(static_cast<unsigned char>(b[18]) & 16u, 0u) << "no tool flag in a version 1 tape";
  for (size_t i = 224; i < 256; ++i) EXPECT_EQ(b[i], 0) << "reserved byte " << i;
  // the records: (10 << 2) | (0 << 1) | 1 = 41; (10 << 2) | (1 << 1) | 0 = 42
  EXPECT_EQ(records_of(b), std::string("\x29\x2a", 2));
  std::remove(p.c_str());
}

TEST(TapeEvents, RoundTripWithEvents) {
  const std::string p = temp_path("ev.tape");
  // draw, lift at 30, two steps up in the air, lower at 100, one more step
  write_small(p, {{0, 1, 10}, {1, 1, 20}, {-1, -1, 30}, {0, 1, 40}, {1, 1, 40}, {-1, 1, 100}, {0, -1, 130}});
  const std::string b = slurp(p);
  EXPECT_EQ(static_cast<unsigned char>(b[8]), 2u);
  uint64_t events = 0;
  std::memcpy(&events, &b[224], 8);
  EXPECT_EQ(events, 2u);
  // the records as docs/tape-format.md spells them: steps (interval << 2 | axis << 1 | up), an event as
  // 0x80 0x00 then (interval << 2 | down)
  const std::string want("\x29"            // 10 ns, r +
                         "\x2b"            // 10 ns, theta +
                         "\x80\x00\x28"    // 10 ns, tool up
                         "\x29"            // 10 ns, r +
                         "\x03"            // 0 ns, theta +
                         "\x80\x00\xf1\x01"  // 60 ns, tool down: (60 << 2) | 1 = 241
                         "\x78",           // 30 ns, r -
                         12);
  EXPECT_EQ(records_of(b), want);
  TapeReader rd(p);
  EXPECT_EQ(rd.header().version, 2);
  EXPECT_EQ(rd.header().event_count, 2u);
  EXPECT_FALSE(rd.header().tool_starts_up);
  std::vector<ToolEvent> ev;
  rd.on_tool_event([&](const ToolEvent& e) { ev.push_back(e); });
  StepRecord r;
  std::vector<uint64_t> intervals;
  while (rd.next(r)) intervals.push_back(r.interval);
  // a step's interval counts from the previous step, across the events
  EXPECT_EQ(intervals, (std::vector<uint64_t>{10, 10, 20, 0, 90}));
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].t_ticks, 30u);
  EXPECT_FALSE(ev[0].down);
  EXPECT_EQ(ev[0].steps_before, 2u);
  EXPECT_EQ(ev[1].t_ticks, 100u);
  EXPECT_TRUE(ev[1].down);
  EXPECT_EQ(ev[1].steps_before, 4u);
  EXPECT_EQ(rd.header().last_step_ticks, 130u);
  EXPECT_NO_THROW(verify_tape(p));
  std::remove(p.c_str());
}

TEST(TapeEvents, AReaderWithoutAHandlerRefusesEventsInOneLine) {
  const std::string p = temp_path("ev2.tape");
  write_small(p, {{0, 1, 10}, {-1, -1, 30}, {-1, 1, 40}, {0, 1, 50}});
  TapeReader rd(p);
  StepRecord r;
  ASSERT_TRUE(rd.next(r));
  try {
    rd.next(r);
    ADD_FAILURE() << "an event read without a handler";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("does not handle tool events"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  std::remove(p.c_str());
}

TEST(TapeEvents, EventsMustAlternate) {
  const std::string p = temp_path("alt.tape");
  {
    TapeHeader h;
    h.res[0] = 1e-5;
    h.res[1] = 1e-3;
    TapeWriter w(p, h);
    EXPECT_THROW(w.tool(true, 5), std::logic_error) << "the tool starts down";
    w.tool(false, 5);
    EXPECT_THROW(w.tool(false, 6), std::logic_error);
  }
  // a tape whose second event is patched from down to up (checksum resealed): the reader names it
  write_small(p, {{0, 1, 10}, {-1, -1, 30}, {-1, 1, 40}, {0, 1, 50}});
  std::string b = slurp(p);
  uint32_t plen = 0;
  std::memcpy(&plen, &b[12], 4);
  const size_t rec = 256 + plen;
  // records: 0x29 | 0x80 0x00 0x50 (20 ns, up) | 0x80 0x00 0x29 (10 ns, down) | 0x29
  ASSERT_EQ(records_of(b), std::string("\x29\x80\x00\x50\x80\x00\x29\x29", 8));
  b[rec + 6] = 0x28;  // 10 ns, up
  put<uint32_t>(b, 216, crc32_bits(b.substr(rec)));
  b = reseal(b);
  const std::string q = temp_path("alt2.tape");
  spit(q, b);
  try {
    verify_tape(q);
    ADD_FAILURE() << "two tool ups in a row accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("alternate"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("tool event 2"), std::string::npos) << e.what();
  }
  // a tape that says it starts with the tool up may start by lowering it
  write_small(p, {{-1, 1, 5}, {0, 1, 10}}, /*starts_up=*/true);
  TapeReader rd(p);
  EXPECT_TRUE(rd.header().tool_starts_up);
  EXPECT_NO_THROW(verify_tape(p));
  // the header's event count is checked against the events read
  write_small(p, {{0, 1, 10}, {-1, -1, 30}, {-1, 1, 40}, {0, 1, 50}});
  b = slurp(p);
  put<uint64_t>(b, 224, 1);
  spit(q, reseal(b));
  EXPECT_THROW(verify_tape(q), InputError);
  std::remove(p.c_str());
  std::remove(q.c_str());
}

TEST(TapeEvents, ReadersThatDoNotHandleEventsRefuseInOneLine) {
  TapeHeader h;
  h.event_count = 2;
  try {
    refuse_tool_events(h, "x.tape", "the error metrics", "measure each contour as a job of its own");
    ADD_FAILURE();
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("x.tape"), std::string::npos) << m;
    EXPECT_NE(m.find("the error metrics does not handle tool events"), std::string::npos) << m;
  }
  h.event_count = 0;
  EXPECT_NO_THROW(refuse_tool_events(h, "x.tape", "the error metrics", ""));
}

}  // namespace tu_digitizer_test_tape
