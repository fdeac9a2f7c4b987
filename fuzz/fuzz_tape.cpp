// Step tapes (digitizer/tape.hpp, docs/tape-format.md): TapeReader on the input written to a file, every record
// read (what verify_tape and `polarcam inspect` do). A tape's two CRC-32s would stop nearly every mutated input at
// the checksums, so when the first byte is odd the rest is made a tape that passes them: the magic, version and
// header size written in, the provenance length cut to the bytes there are, the records' byte count and both
// checksums computed.
#include <zlib.h>

#include <cstring>
#include <vector>

#include "digitizer/tape.hpp"
#include "fuzz/fuzz_common.hpp"

namespace {
void put_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
uint32_t get_u32(const uint8_t* p) { return p[0] | p[1] << 8 | p[2] << 16 | static_cast<uint32_t>(p[3]) << 24; }

std::vector<uint8_t> with_checksums(const uint8_t* data, size_t size) {
  constexpr size_t kFixed = polarcam::kTapeFixedHeader;
  std::vector<uint8_t> t(data, data + size);
  if (t.size() < kFixed) t.resize(kFixed, 0);
  std::memcpy(t.data(), "POLARCAM", 8);
  t[8] = static_cast<uint8_t>(polarcam::kTapeVersion);
  t[9] = static_cast<uint8_t>(polarcam::kTapeVersion >> 8);
  t[10] = static_cast<uint8_t>(kFixed);
  t[11] = static_cast<uint8_t>(kFixed >> 8);
  const uint32_t plen = static_cast<uint32_t>(std::min<size_t>(get_u32(&t[12]), t.size() - kFixed));
  put_u32(&t[12], plen);
  const size_t header = kFixed + plen;
  const uint64_t records = t.size() - header;
  for (int i = 0; i < 8; ++i) t[192 + i] = static_cast<uint8_t>(records >> (8 * i));
  put_u32(&t[216], static_cast<uint32_t>(crc32(0L, t.data() + header, static_cast<uInt>(t.size() - header))));
  put_u32(&t[220], 0);
  put_u32(&t[220], static_cast<uint32_t>(crc32(0L, t.data(), static_cast<uInt>(header))));
  return t;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string path;
  if (size > 0 && (data[0] & 1)) {
    const std::vector<uint8_t> t = with_checksums(data + 1, size - 1);
    path = polarcam::fuzz::write_input(t.data(), t.size(), "fuzz.tape");
  } else {
    path = polarcam::fuzz::write_input(data, size, "fuzz.tape");
  }
  polarcam::fuzz::expect_typed([&] {
    polarcam::TapeReader rd(path);
    polarcam::StepRecord r;
    while (rd.next(r)) {
    }
  });
  return 0;
}
