// SVG drawings (cam/svg_import.hpp): parse_svg on the text held in memory.
#include "cam/svg_import.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  polarcam::fuzz::expect_typed(
      [&] { polarcam::parse_svg(std::string(polarcam::fuzz::as_text(data, size)), "fuzz.svg"); });
  return 0;
}
