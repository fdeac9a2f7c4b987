#pragma once
// A per-process scratch file name, for tests of any library.
#include <unistd.h>

#include <string>

namespace polarcam::test {

inline std::string temp_path(const std::string& name) {
  return "/tmp/polarcam-test-" + std::to_string(::getpid()) + "-" + name;
}

}  // namespace polarcam::test
