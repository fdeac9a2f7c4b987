#pragma once
// Example tapes for the player's tests, digitized in-process from the examples' job files.
#include <cstdio>
#include <string>
#include <vector>

#include "job/job.hpp"
#include "pipeline/job_tape.hpp"
#include "tests/helpers.hpp"

namespace polarcam::test {

// Digitizes examples/<name>.toml into a temporary tape (once per test process) and returns its path.
inline std::string example_tape(const std::string& name) {
  struct Cleanup {
    std::vector<std::string> files;
    ~Cleanup() {
      for (const auto& f : files) std::remove(f.c_str());
    }
  };
  static Cleanup cleanup;
  const std::string path = temp_path(name + ".tape");
  if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    std::fclose(f);
    return path;
  }
  Job job = load_job(std::string(POLARCAM_SOURCE_DIR) + "/examples/" + name + ".toml");
  TapeHeader h = tape_header_for(job);
  TapeWriter w(path, h);
  DigitizedJob d = digitize_job(job, &w);
  complete_header(h, d.result);
  w.finish(h);
  cleanup.files.push_back(path);
  return path;
}

}  // namespace polarcam::test
