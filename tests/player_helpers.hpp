#pragma once
// For the player's and the controller's tests: the examples' tapes, a tape read record by record with no player
// code, and play scalings from their command-line spelling.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "digitizer/tape.hpp"
#include "machine/player/scaling.hpp"
#include "machine/player/schedule.hpp"
#include "tests/example_tapes.hpp"

namespace polarcam::test {

struct TapeStep {
  int axis, dir;
  uint64_t t;      // tape ticks
  int64_t n, m;    // tape node after the step
};

// The tape read record by record, with no player code.
inline std::vector<TapeStep> read_tape(const std::string& path) {
  TapeReader rd(path);
  std::vector<TapeStep> v;
  StepRecord r;
  uint64_t t = 0;
  int64_t n = rd.header().start[0], m = rd.header().start[1];
  while (rd.next(r)) {
    t += r.interval;
    (r.axis == 0 ? n : m) += r.dir;
    v.push_back({r.axis, r.dir, t, n, m});
  }
  return v;
}

inline PlayScaling scaling(const std::string& speed, const std::string& size = "1", int64_t offset = 0) {
  PlayScaling s;
  s.speed = parse_ratio(speed, "--speed-scale");
  s.size = parse_ratio(size, "--size-scale");
  s.angle_offset = offset;
  return s;
}

// Encodes `items` and decodes them back: every field each item's kind uses comes back, and nothing is left over.
inline void expect_codec_round_trip(const std::vector<QueueItem>& items) {
  ItemCodec enc, dec;
  std::string bytes;
  for (const QueueItem& it : items) enc.encode(it, bytes);
  const auto* d = reinterpret_cast<const uint8_t*>(bytes.data());
  size_t pos = 0;
  for (size_t i = 0; i < items.size(); ++i) {
    const QueueItem& it = items[i];
    QueueItem got;
    ASSERT_TRUE(dec.decode(d, bytes.size(), pos, got)) << "item " << i;
    ASSERT_EQ(got.kind, it.kind) << "item " << i;
    ASSERT_EQ(got.axis, it.axis) << "item " << i;
    if (it.kind == ItemKind::wait) {
      ASSERT_EQ(got.wait, it.wait) << "item " << i;
    }
    if (it.kind != ItemKind::run) continue;
    ASSERT_EQ(got.dir, it.dir) << "item " << i;
    ASSERT_EQ(got.count, it.count) << "item " << i;
    ASSERT_EQ(got.offset, it.offset) << "item " << i;
    ASSERT_EQ(got.interval, it.interval) << "item " << i;
    ASSERT_EQ(got.add, it.add) << "item " << i;
    ASSERT_EQ(got.add2, it.add2) << "item " << i;
  }
  EXPECT_EQ(pos, bytes.size());
}

}  // namespace polarcam::test
