// The serial protocol's frames through noise and damage, and the simulated line's fault specification.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "cam/error.hpp"
#include "machine/link/protocol.hpp"
#include "machine/link/sim_line.hpp"

namespace polarcam {
namespace {

TEST(Protocol, FramesSurviveNoiseAndDamagedFramesAreRejected) {
  std::string stream;
  std::vector<std::string> payloads;
  std::mt19937 rng(3);
  for (int i = 0; i < 200; ++i) {
    std::string p(static_cast<size_t>(rng() % 60), '\0');
    for (char& c : p) c = static_cast<char>(rng() % 256);
    if (i % 7 == 0) p += std::string(3, static_cast<char>(proto::kSync));  // sync bytes inside payloads
    payloads.push_back(p);
    std::string f = proto::encode_frame(static_cast<uint16_t>(i), proto::QUEUE, p);
    if (i % 5 == 1) f[3 + rng() % (f.size() - 3)] ^= 0x10;  // damage: this frame must not come out
    stream += f;
    if (i % 11 == 0) stream += "\x7e\x05garbage";
  }
  proto::FrameDecoder dec;
  std::vector<proto::Frame> out;
  for (size_t pos = 0; pos < stream.size(); pos += 13)  // fed in odd-sized pieces
    dec.feed(reinterpret_cast<const uint8_t*>(stream.data() + pos), std::min<size_t>(13, stream.size() - pos), out);
  size_t k = 0;
  for (int i = 0; i < 200; ++i) {
    if (i % 5 == 1) continue;
    ASSERT_LT(k, out.size());
    EXPECT_EQ(out[k].seq, i);
    EXPECT_EQ(out[k].type, proto::QUEUE);
    EXPECT_EQ(out[k].payload, payloads[static_cast<size_t>(i)]);
    ++k;
  }
  EXPECT_EQ(k, out.size());
  EXPECT_GE(dec.bad_frames(), 40u);
}

TEST(Protocol, FaultSpecParsesAndNamesBadItems) {
  FaultSpec f = parse_faults("drop=0.01,corrupt=0.02,delay=0.001,delay_ms=5,stall=2@3,disconnect=1@4,reset@6,seed=9");
  EXPECT_DOUBLE_EQ(f.drop, 0.01);
  EXPECT_DOUBLE_EQ(f.corrupt, 0.02);
  EXPECT_DOUBLE_EQ(f.delay_s, 0.005);
  EXPECT_DOUBLE_EQ(f.stall_at, 3);
  EXPECT_DOUBLE_EQ(f.stall_s, 2);
  EXPECT_DOUBLE_EQ(f.disconnect_at, 4);
  EXPECT_DOUBLE_EQ(f.reset_at, 6);
  EXPECT_EQ(f.seed, 9u);
  EXPECT_THROW(parse_faults("drop=2"), InputError);
  EXPECT_THROW(parse_faults("lose=0.1"), InputError);
  EXPECT_THROW(parse_faults("stall=3"), InputError);
}

}  // namespace
}  // namespace polarcam
