// DXF drawings (cam/dxf_import.hpp): read_dxf_path on the input written to a file (dxflib reads files only), once
// with every layer and once with layer "0".
#include "cam/dxf_import.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = polarcam::fuzz::write_input(data, size, "fuzz.dxf");
  polarcam::DxfOptions all;
  polarcam::fuzz::expect_typed([&] { polarcam::read_dxf_path(path, all); });
  polarcam::DxfOptions layer0;
  layer0.layer = "0";
  polarcam::fuzz::expect_typed([&] { polarcam::read_dxf_path(path, layer0); });
  return 0;
}
