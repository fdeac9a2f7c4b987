// Drives files (machine/servo/drives_file.hpp, docs/feed-drives.md): read_drives_file on the input written as
// drives.toml.
#include "fuzz/fuzz_common.hpp"
#include "machine/servo/drives_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = polarcam::fuzz::write_input(data, size, "drives.toml");
  polarcam::fuzz::expect_typed([&] { polarcam::servo::read_drives_file(path); });
  return 0;
}
