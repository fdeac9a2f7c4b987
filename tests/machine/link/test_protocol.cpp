// The serial protocol's frames through noise and damage, and the simulated line's fault specification.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "cam/error.hpp"
#include "machine/link/protocol.hpp"
#include "machine/link/sim_line.hpp"
#include "machine/link/wire.hpp"
#include "machine/player/int128.hpp"

namespace polarcam {
namespace tu_machine_link_test_protocol {  // named: the test files compile together

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

// The shared wire's CRC (four bits at a time, no library: the firmware has none) against zlib's, piece by piece.
TEST(Protocol, WireCrcIsZlibs) {
  std::mt19937 rng(11);
  for (int len : {0, 1, 2, 7, 64, 250, 1000}) {
    std::vector<uint8_t> d(static_cast<size_t>(len));
    for (uint8_t& b : d) b = static_cast<uint8_t>(rng());
    const auto z = static_cast<uint32_t>(crc32(0L, d.data(), static_cast<uInt>(d.size())));
    EXPECT_EQ(wire::crc32(0, d.data(), d.size()), z) << len << " bytes";
    const size_t half = d.size() / 2;  // continued over two pieces, as zlib's
    EXPECT_EQ(wire::crc32(wire::crc32(0, d.data(), half), d.data() + half, d.size() - half), z);
  }
  const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(wire::crc32(0, check, 9), 0xCBF43926u);  // the CRC-32 check value of "123456789"
}

// A frame built by hand (the layout of the protocol's specification) decodes; the wire's encoder writes the same.
TEST(Protocol, FrameLayoutByHand) {
  std::string f = "\x7e\x05\xfa\x34\x12\x03\xaa\xbb";
  const auto c = static_cast<uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(f.data() + 1), 7));
  for (int i = 0; i < 4; ++i) f.push_back(static_cast<char>((c >> (8 * i)) & 0xff));
  EXPECT_EQ(proto::encode_frame(0x1234, proto::QUEUE, "\xaa\xbb"), f);
  proto::FrameDecoder dec;
  std::vector<proto::Frame> out;
  dec.feed(reinterpret_cast<const uint8_t*>(f.data()), f.size(), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].seq, 0x1234);
  EXPECT_EQ(out[0].payload, "\xaa\xbb");
}

// IDENT (version 5) carries the largest step rate (since version 3) and the capabilities, then the name; an IDENT
// of another version still names its version.
TEST(Protocol, IdentVersion5AndOtherVersionsNamed) {
  proto::Ident id;
  id.tick_ps = 4000000;
  id.slots = 24;
  id.session = 7;
  id.max_step_rate = 20000;
  id.caps = 1;
  id.name = "board";
  const std::string p = id.encode();
  ASSERT_EQ(p.size(), 1u + 8 + 4 + 4 + 4 + 1 + 1 + 5);
  EXPECT_EQ(static_cast<uint8_t>(p[0]), 5);
  EXPECT_EQ(static_cast<uint8_t>(p[17]) | static_cast<uint8_t>(p[18]) << 8, 20000 & 0xffff);  // after the session
  EXPECT_EQ(static_cast<uint8_t>(p[21]), 1);  // the tool capability, after the step rate
  EXPECT_EQ(static_cast<uint8_t>(p[22]), 5);  // the name's length
  proto::Ident back;
  ASSERT_TRUE(proto::Ident::decode(p, back));
  EXPECT_EQ(back.tick_ps, 4000000u);
  EXPECT_EQ(back.slots, 24u);
  EXPECT_EQ(back.max_step_rate, 20000u);
  EXPECT_EQ(back.caps, 1);
  EXPECT_EQ(back.name, "board");
  std::string v4 = p;
  v4[0] = 4;
  v4.erase(21, 1);  // version 4 had no capabilities
  proto::Ident four;
  EXPECT_FALSE(proto::Ident::decode(v4, four));
  EXPECT_EQ(four.version, 4);
  std::string v2 = p;
  v2[0] = 2;
  v2.erase(17, 4);  // version 2 had no step rate
  proto::Ident old;
  EXPECT_FALSE(proto::Ident::decode(v2, old));
  EXPECT_EQ(old.version, 2);
}

// Version 4: ACK and STATUS_REPLY end with the queue's free bytes (all ones: not limited), NAK with whether the
// frames after the missing one were kept.
TEST(Protocol, AckStatusAndNakOfVersion4) {
  proto::Ack a;
  a.next_seq = 0x0102;
  a.free_slots = 0x03040506;
  a.state = 2;
  EXPECT_EQ(a.encode(), std::string("\x02\x01\x06\x05\x04\x03\x02\xff\xff\xff\xff", 11));
  a.free_bytes = 384;
  const std::string p = a.encode();
  ASSERT_EQ(p.size(), 11u);
  EXPECT_EQ(static_cast<uint8_t>(p[7]) | static_cast<uint8_t>(p[8]) << 8, 384);
  proto::Ack back;
  ASSERT_TRUE(proto::Ack::decode(p, back));
  EXPECT_EQ(back.free_bytes, 384u);
  EXPECT_FALSE(proto::Ack::decode(p.substr(0, 7), back));  // a version 3 ACK
  proto::Status st;
  st.free_bytes = 0x0a0b0c0d;
  const std::string s = st.encode();
  ASSERT_EQ(s.size(), 76u);  // 72 bytes of version 3, then free_bytes
  EXPECT_EQ(s.substr(72), std::string("\x0d\x0c\x0b\x0a", 4));
  proto::Status sb;
  ASSERT_TRUE(proto::Status::decode(s, sb));
  EXPECT_EQ(sb.free_bytes, 0x0a0b0c0du);
  wire::Nak n;
  const uint8_t dropped[3] = {0x34, 0x12, 0};
  ASSERT_TRUE(n.decode(dropped, 3));
  EXPECT_EQ(n.next_seq, 0x1234);
  EXPECT_EQ(n.kept, 0);
  const uint8_t bad[3] = {0x34, 0x12, 2};
  EXPECT_FALSE(n.decode(bad, 3));
  EXPECT_FALSE(n.decode(dropped, 2));  // a version 3 NAK
}

// The wire's 128-bit stand-in (the firmware has no __int128) against the compiler's.
TEST(Protocol, WideArithmeticMatchesInt128) {
  std::mt19937_64 rng(5);
  for (int i = 0; i < 20000; ++i) {
    const auto v = static_cast<int64_t>(rng()) >> (rng() % 64);
    const auto m = static_cast<uint32_t>(rng() >> (rng() % 64));
    const auto w = static_cast<int64_t>(rng()) >> (rng() % 64);
    const i128 want = static_cast<i128>(v) * m + w;
    const wire::Wide got = wire::Wide::mul(v, m) + wire::Wide::of(w);
    ASSERT_EQ(got.lo, static_cast<uint64_t>(want)) << v << " * " << m << " + " << w;
    ASSERT_EQ(got.hi, static_cast<int64_t>(want >> 64)) << v << " * " << m << " + " << w;
    const i128 other = static_cast<i128>(w) * 3;
    ASSERT_EQ(got < wire::Wide::mul(w, 3), want < other);
  }
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

}  // namespace tu_machine_link_test_protocol
}  // namespace polarcam
