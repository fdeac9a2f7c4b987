// CSV point lists (cam/point_files.hpp): read_points_csv on the input written to a file.
#include "cam/point_files.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = polarcam::fuzz::write_input(data, size, "fuzz.csv");
  polarcam::fuzz::expect_typed([&] { polarcam::read_points_csv(path, 1e-3); });
  return 0;
}
