#include "io/output.hpp"

#include "cam/format.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "cam/error.hpp"
#include "cam/units.hpp"

namespace polarcam::cli {

void write_file_atomic(const std::string& path, const std::string& content) {
  std::string tmp = path + ".partial-" + std::to_string(::getpid());
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw DeviceError(std::string("cannot create the file (") + std::strerror(errno) + ")", path);
  bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  ok = (std::fclose(f) == 0) && ok;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
    int e = errno;
    std::remove(tmp.c_str());
    throw DeviceError(std::string("cannot write the file (") + std::strerror(e) + ")", path);
  }
}

std::string thousands(unsigned long long v) {
  std::string s = std::to_string(v), out;
  int n = 0;
  for (auto it = s.rbegin(); it != s.rend(); ++it) {
    if (n && n % 3 == 0) out.insert(out.begin(), ',');
    out.insert(out.begin(), *it);
    ++n;
  }
  return out;
}

std::string significant(double v, int digits) { return polarcam::significant(v, digits); }

double parse_rate_option(const std::string& text) {
  try {
    Quantity q = parse_quantity(text);
    if (q.dim != dim::none && q.dim != dim::frequency) throw InputError("'" + text + "' is not a frequency");
    if (!(q.value > 0.0) || q.value > 1e9) throw InputError("the interrupt rate must be above 0 and up to 1 GHz");
    return q.value;
  } catch (const InputError& e) {
    throw InputError(std::string("--rate: ") + e.what());
  }
}

}  // namespace polarcam::cli
