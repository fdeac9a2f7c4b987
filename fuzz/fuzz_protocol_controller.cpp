// The controller side of the protocol (machine/controller/controller.hpp, what the emulator and the firmware
// run): what a host (or a damaged line) sends is the input, delivered in pieces of 1..32 bytes, 2 ms of
// controller time apart, the schedule executed between them and for 0.2 s after the last; every frame of the
// input also goes through the payload decoders.
#include "fuzz/protocol_frames.hpp"
#include "machine/controller/controller.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace polarcam;
  const std::string stream = fuzz::protocol_stream(data, size);
  fuzz::decode_payloads(stream);
  fuzz::expect_typed([&] {
    ControllerSpec spec;  // 1 us tick, 4096 slots
    spec.slots = 64;
    Controller c(spec);
    uint64_t steps = 0;
    c.on_step = [&](uint64_t, int, int) { ++steps; };
    uint64_t now = 0;
    for (size_t pos = 0; pos < stream.size();) {
      const size_t n = std::min<size_t>(stream.size() - pos, 1 + static_cast<uint8_t>(stream[pos]) % 32);
      c.receive(reinterpret_cast<const uint8_t*>(stream.data() + pos), n, now);
      pos += n;
      now += 2000;
      c.advance(now);
      c.take_output();
    }
    c.advance(now + 200000);
    c.take_output();
  });
  return 0;
}
