#pragma once
// For the player's and the controller's tests: the examples' tapes, a tape read record by record with no player
// code, and play scalings from their command-line spelling.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "digitizer/tape.hpp"
#include "machine/player/scaling.hpp"
#include "machine/player/schedule.hpp"
#include "tests/example_tapes.hpp"
#include "tests/temp_path.hpp"

namespace polarcam::test {

struct TapeStep {
  int axis, dir;
  uint64_t t;      // tape ticks
  int64_t n, m;    // tape node after the step
};

// The tape read record by record, with no player code (its steps; a version 2 tape's tool events are passed over,
// their time counted in the next step's).
inline std::vector<TapeStep> read_tape(const std::string& path) {
  TapeReader rd(path);
  rd.on_tool_event([](const ToolEvent&) {});
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

// A tape of two strokes with the tool lifted between them, written by hand (tape ticks of 1 ns): stroke A, 200
// steps alternating r+ and theta+ every 50 us from t = 50 us; the tool up 30 us after A's last step; a rapid of 100
// r+ steps every 20 us; the tool down at the time of the rapid's last step (an interval of 0); stroke B, 200
// theta- steps every 40 us. kLift* are those times and the steps before each event.
inline constexpr uint64_t kLiftUpNs = 200 * 50000 + 30000;                    // after 200 steps
inline constexpr uint64_t kLiftDownNs = kLiftUpNs + 100 * 20000;              // after 300 steps
inline constexpr uint64_t kLiftLastNs = kLiftDownNs + 200 * 40000;            // the last of 500 steps
inline std::string lifting_tape() {
  struct Cleanup {
    std::string file;
    ~Cleanup() {
      if (!file.empty()) std::remove(file.c_str());
    }
  };
  static Cleanup cleanup;
  if (!cleanup.file.empty()) return cleanup.file;
  const std::string path = temp_path("lifting.tape");
  TapeHeader h;
  h.res[0] = 0.0254e-3;
  h.steps_per_rev = 16000;
  h.res[1] = dtheta_from_steps(h.steps_per_rev);
  h.r_min = 0.0;
  h.has_r_max = true;
  h.r_max = 0.3;
  h.speed_mps = 0.01;
  h.home[0] = 0, h.home[1] = 0;
  h.start[0] = 2000, h.start[1] = 100;
  TapeWriter w(path, h);
  uint64_t t = 0;
  for (int k = 0; k < 200; ++k) w.step(k % 2, +1, static_cast<int64_t>(t += 50000));
  w.tool(false, static_cast<int64_t>(t += 30000));
  for (int k = 0; k < 100; ++k) w.step(0, +1, static_cast<int64_t>(t += 20000));
  w.tool(true, static_cast<int64_t>(t));
  for (int k = 0; k < 200; ++k) w.step(1, -1, static_cast<int64_t>(t += 40000));
  h.end[0] = 2000 + 100 + 100, h.end[1] = 100 + 100 - 200;
  h.duration_ticks = t;
  w.finish(h);
  cleanup.file = path;
  return path;
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
    if (it.kind == ItemKind::wait || it.kind == ItemKind::tool) {
      ASSERT_EQ(got.wait, it.wait) << "item " << i;
    }
    if (it.kind == ItemKind::tool) {
      ASSERT_EQ(got.dir, it.dir) << "item " << i;
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
