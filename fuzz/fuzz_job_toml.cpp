// Job files (job/job.hpp, docs/job-format.md): load_job on the input written as job.toml in a directory of its
// own (a machine file or a point file the job names relative to itself is not there: an input error).
#include "fuzz/fuzz_common.hpp"
#include "job/job.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = polarcam::fuzz::write_input(data, size, "job.toml");
  polarcam::fuzz::expect_typed([&] { polarcam::load_job(path); });
  return 0;
}
