// Theta-rho pattern files (cam/thr_file.hpp): parse_thr on the bytes held in memory, then the pattern's
// statistics (what `polarcam check` prints).
#include <sstream>

#include "cam/thr_file.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  polarcam::fuzz::expect_typed([&] {
    std::istringstream in(std::string(polarcam::fuzz::as_text(data, size)));
    polarcam::ThrPattern p = polarcam::parse_thr(in, "fuzz.thr");
    polarcam::thr_stats(p.vertices);
  });
  return 0;
}
