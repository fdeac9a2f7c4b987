#pragma once
// Scratch files for tests that write job files: reading a file whole, editing a good job into a bad one, and a
// scratch directory with the examples' machine file. No library and no executable needed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace polarcam::test {

inline std::string read_file(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// `s` with the first occurrence of `from` replaced by `to` (a failed expectation when `from` is missing): the bad
// job files of the CLI tests are a good one with one thing changed.
inline std::string replace(std::string s, const std::string& from, const std::string& to) {
  auto p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  if (p != std::string::npos) s.replace(p, from.size(), to);
  return s;
}

// A job file of the CLI tests (tests/data/cli/<name>), as text.
inline std::string cli_job(const std::string& name) {
  return read_file((std::filesystem::path(POLARCAM_SOURCE_DIR) / "tests" / "data" / "cli" / name).string());
}

// A scratch directory with the examples' machine file, removed at the end of the test.
struct Scratch {
  std::filesystem::path dir;
  Scratch() {
    dir = std::filesystem::temp_directory_path() / ("polarcam-scratch-" + std::to_string(::getpid()) + "-" +
                                                    std::to_string(reinterpret_cast<uintptr_t>(this)));
    std::filesystem::create_directories(dir / "machines");
    std::filesystem::copy_file(std::string(POLARCAM_SOURCE_DIR) + "/examples/machines/fahim1983.toml",
                               dir / "machines" / "fahim1983.toml");
  }
  ~Scratch() { std::filesystem::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }
};

}  // namespace polarcam::test
