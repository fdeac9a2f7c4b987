// Template images (cam/image_trace.hpp): parse_image on the bytes (PNG through libpng, PBM/PGM through polarcam's
// reader) and, for an image small enough to trace quickly, the tracing with a given pixel size.
#include "cam/image_trace.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace polarcam;
  fuzz::expect_typed([&] {
    const GrayImage im = parse_image(std::string(fuzz::as_text(data, size)), "fuzz.png");
    if (static_cast<long long>(im.width) * im.height <= 256 * 256) {
      TraceOptions o;
      o.pixel_size_m = 1e-4;
      trace_image(im, o, "fuzz.png");
    }
  });
  return 0;
}
