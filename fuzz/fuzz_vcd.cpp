// Encoder recordings (capture/capture.hpp): decode_capture of the bytes as a VCD file and as a CSV file, with the
// default options (the four channels r_a r_b theta_a theta_b, one step per count, no sink), and as a step/dir
// recording (r_step r_dir theta_step theta_dir, time 0 at the rising edge of `run`).
#include <sstream>

#include "capture/capture.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace polarcam;
  const std::string text(fuzz::as_text(data, size));
  CaptureOptions step_dir;
  step_dir.encoding = CaptureEncoding::step_dir;
  step_dir.origin_signal = "run";
  for (CaptureFormat f : {CaptureFormat::vcd, CaptureFormat::csv})
    for (const CaptureOptions& o : {CaptureOptions{}, step_dir})
      fuzz::expect_typed([&] {
        std::istringstream in(text);
        decode_capture(in, "fuzz", f, o, nullptr);
      });
  return 0;
}
