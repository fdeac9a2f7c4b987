// Machine files (job/job.hpp, docs/job-format.md): load_machine on the input written as machine.toml, with the
// machine's canonical description.
#include "fuzz/fuzz_common.hpp"
#include "job/job.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = polarcam::fuzz::write_input(data, size, "machine.toml");
  polarcam::fuzz::expect_typed([&] {
    nlohmann::ordered_json prov;
    polarcam::load_machine(path, &prov);
  });
  return 0;
}
