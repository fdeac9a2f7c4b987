#pragma once
// The byte stream of the protocol harnesses (fuzz_protocol_host, fuzz_protocol_controller). Frames carry a
// CRC-32, which random mutations almost never keep right; so when the first byte is odd the rest is read as
// records [TYPE u8][SEQ u16 LE][LEN u8][LEN bytes of payload], each sent as a well-formed frame (encode_frame),
// and when it is even the rest is sent as it is (sync, lengths and CRCs as the fuzzer made them).
#include <string>

#include "fuzz/fuzz_common.hpp"
#include "machine/link/protocol.hpp"

namespace polarcam::fuzz {

inline std::string protocol_stream(const uint8_t* data, size_t size) {
  Bytes b{data, size};
  const bool framed = b.u8() & 1;
  if (!framed) return b.take(b.n);
  std::string out;
  while (!b.empty()) {
    const uint8_t type = b.u8();
    const uint16_t seq = b.u16();
    const size_t len = b.u8() % (proto::kMaxPayload + 1);
    out += proto::encode_frame(seq, type, b.take(len));
  }
  return out;
}

// Every frame of the stream and every payload decoder on it (what either side does with a frame's payload).
inline void decode_payloads(const std::string& stream) {
  proto::FrameDecoder dec;
  std::vector<proto::Frame> frames;
  dec.feed(reinterpret_cast<const uint8_t*>(stream.data()), stream.size(), frames);
  for (const proto::Frame& f : frames) {
    proto::Ident id;
    proto::Ident::decode(f.payload, id);
    proto::Configure c;
    proto::Configure::decode(f.payload, c);
    proto::Ack a;
    proto::Ack::decode(f.payload, a);
    proto::Status s;
    proto::Status::decode(f.payload, s);
    proto::ErrorMsg e;
    proto::ErrorMsg::decode(f.payload, e);
  }
}

}  // namespace polarcam::fuzz
