// The option values the commands parse themselves: --rate (io/output.hpp), --size-scale and --speed-scale
// ratios (machine/player/scaling.hpp), controller-sim --faults (machine/link/sim_line.hpp).
#include "fuzz/fuzz_common.hpp"
#include "io/output.hpp"
#include "machine/link/sim_line.hpp"
#include "machine/player/scaling.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace polarcam;
  const std::string text(fuzz::as_text(data, size));
  fuzz::expect_typed([&] { cli::parse_rate_option(text); });
  fuzz::expect_typed([&] { to_string(parse_ratio(text, "--size-scale")); });
  fuzz::expect_typed([&] { to_string(parse_faults(text)); });
  return 0;
}
