#pragma once
// What every harness shares (docs/fuzzing.md): the input as a file for the parsers that read files, and the rule
// that a typed error (cam/error.hpp: bad input, a device) is a correct answer to bad bytes while anything else
// escaping the parser (another exception, a crash, a sanitizer report, a leak, a hang) is a finding.
#include <fcntl.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "cam/error.hpp"

namespace polarcam::fuzz {

// A private directory made once per process (and left behind: a few small files) (so that a job naming "machine.toml" or "points.csv" finds nothing
// the fuzzer did not write), and the input written into it under one name, rewritten for every input.
inline const std::string& private_dir() {
  static const std::string dir = [] {
    // in memory (tmpfs) where there is one: a file is written for every input
    char shm[] = "/dev/shm/polarcam-fuzz-XXXXXX", tmp[] = "/tmp/polarcam-fuzz-XXXXXX";
    if (mkdtemp(shm)) return std::string(shm);
    if (!mkdtemp(tmp)) std::abort();
    return std::string(tmp);
  }();
  return dir;
}

inline std::string write_input(const uint8_t* data, size_t size, const std::string& name) {
  std::string path = private_dir() + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  if (std::fclose(f) != 0) std::abort();
  return path;
}

inline std::string_view as_text(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// The lowest free file descriptor: the same before and after a parse unless the parse left a file open.
inline int lowest_free_fd() {
  const int fd = ::open("/dev/null", O_RDONLY);
  if (fd < 0) std::abort();
  ::close(fd);
  return fd;
}

// Runs f(); a polarcam::Error of kind input or device (the documented answers to bad input) is fine. Anything else
// propagates out of LLVMFuzzerTestOneInput and libFuzzer reports it (an uncaught exception aborts), and so is a
// file left open (accepted or refused, a parser closes what it opened).
template <class F>
void expect_typed(F&& f) {
  const int fd = lowest_free_fd();
  try {
    f();
  } catch (const polarcam::Error& e) {
    if (e.kind() == polarcam::ErrorKind::internal) throw;
  }
  if (lowest_free_fd() != fd) {
    std::fprintf(stderr, "polarcam fuzz: the parser left a file open\n");
    std::abort();
  }
}

// Consumes bytes from the front of the input.
struct Bytes {
  const uint8_t* p;
  size_t n;
  bool empty() const { return n == 0; }
  uint8_t u8() {
    if (n == 0) return 0;
    --n;
    return *p++;
  }
  uint16_t u16() { return static_cast<uint16_t>(u8() | (u8() << 8)); }
  std::string take(size_t k) {
    if (k > n) k = n;
    std::string s(reinterpret_cast<const char*>(p), k);
    p += k;
    n -= k;
    return s;
  }
};

}  // namespace polarcam::fuzz
