#pragma once
// LinuxCNC's standalone G-code interpreter (rs274, Debian package linuxcnc-uspace) on a program file, for the tests
// that check polarcam's G-code against it. The test target defines POLARCAM_RS274 (tests/CMakeLists.txt).
//
// rs274 keeps its tool table in $HOME/.tool.mmap, which every run creates, truncates and maps: two runs at once (ctest
// --parallel) truncate each other's mapping, and one of them dies of SIGBUS. Each run here has a HOME of its own.
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

namespace polarcam::test {

struct Rs274Run {
  int status = -1;       // rs274's exit status; -1 when it did not exit (a signal)
  std::string out, err;  // its standard output (the canonical calls) and error output
};

inline Rs274Run run_rs274(const std::string& program_file) {
  char home[] = "/tmp/polarcam-rs274-XXXXXX";
  if (::mkdtemp(home) == nullptr) throw std::runtime_error("cannot make a home directory for rs274");
  const std::string dir = home, out = dir + "/out", err = dir + "/err";
  const std::string cmd = "HOME=" + dir + " " + std::string(POLARCAM_RS274) + " -g '" + program_file +
                          "' </dev/null >" + out + " 2>" + err;
  Rs274Run r;
  const int st = std::system(cmd.c_str());
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  r.out = slurp(out);
  r.err = slurp(err);
  for (const std::string& f : {out, err, dir + "/.tool.mmap"}) std::remove(f.c_str());
  ::rmdir(dir.c_str());
  return r;
}

}  // namespace polarcam::test
