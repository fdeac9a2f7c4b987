#pragma once
// Numbers in messages and reports: v to `digits` significant digits, as a stream prints it by default
// ("0.0254", "1.5e+06").
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>

namespace polarcam {

inline std::string significant(double v, int digits = 6) {
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}

// A count and its noun, singular for one: count_of(1, "hole") is "1 hole", count_of(3, "hole") "3 holes".
inline std::string count_of(uint64_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

// A number for a reader, never in exponent form: `digits` significant digits below 10^digits, the nearest whole
// number above ("0.0254", "57.6", "2910", "55500"). For ratios and factors in messages, not for data.
inline std::string plain(double v, int digits = 3) {
  if (!std::isfinite(v)) return v != v ? "nan" : v > 0 ? "infinite" : "-infinite";
  if (std::abs(v) >= std::pow(10.0, digits)) return significant(std::round(v), 17);
  return significant(v, digits);
}

// A fraction for a reader: as a percentage below 1000 % ("57.6 %", "-20 %"), beyond that as a plain ratio
// ("57.6 times", "2910 times"): a percentage in the thousands, in exponent form ("5.76e+03 %"), says nothing the ratio does not.
inline std::string share(double fraction, int digits = 3) {
  if (!(std::abs(fraction) < 10.0)) return plain(fraction, digits) + " times";
  return significant(100.0 * fraction, digits) + " %";
}

// Text for XML and HTML (SVG titles, report text, attribute values in double quotes): & < > " escaped; the control
// characters XML 1.0 forbids (below 0x20 other than tab, line feed and carriage return) dropped.
inline std::string xml_escape(std::string_view s) {
  std::string o;
  o.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default:
        if (static_cast<unsigned char>(c) >= 0x20 || c == '\t' || c == '\n' || c == '\r') o += c;
    }
  }
  return o;
}

}  // namespace polarcam
