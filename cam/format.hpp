#pragma once
// Numbers in messages and reports: v to `digits` significant digits, as a stream prints it by default
// ("0.0254", "1.5e+06").
#include <sstream>
#include <string>

namespace polarcam {

inline std::string significant(double v, int digits = 6) {
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}

}  // namespace polarcam
