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

// Text for one line of a terminal (the error messages, which may quote bytes of a damaged input file): control
// characters, DEL and bytes that are not part of well-formed UTF-8 written as \xNN, so that a message never moves the
// cursor, rings, changes the terminal's state or breaks the line; well-formed UTF-8 (units, dashes) kept.
inline std::string terminal_text(std::string_view s) {
  static const char* hex = "0123456789abcdef";
  std::string o;
  o.reserve(s.size());
  auto escape = [&](unsigned char b) {
    o += "\\x";
    o += hex[b >> 4];
    o += hex[b & 15];
  };
  for (size_t i = 0; i < s.size();) {
    const unsigned char b = static_cast<unsigned char>(s[i]);
    if (b >= 0x20 && b < 0x7f) {
      o += static_cast<char>(b);
      ++i;
      continue;
    }
    // the length of a well-formed UTF-8 sequence starting here (0: none), RFC 3629's table
    size_t n = 0;
    auto cont = [&](size_t k, unsigned char lo = 0x80, unsigned char hi = 0xbf) {
      if (i + k >= s.size()) return false;
      const unsigned char c = static_cast<unsigned char>(s[i + k]);
      return c >= lo && c <= hi;
    };
    if (b >= 0xc2 && b <= 0xdf && cont(1)) n = 2;
    else if (b == 0xe0 && cont(1, 0xa0) && cont(2)) n = 3;
    else if (((b >= 0xe1 && b <= 0xec) || b == 0xee || b == 0xef) && cont(1) && cont(2)) n = 3;
    else if (b == 0xed && cont(1, 0x80, 0x9f) && cont(2)) n = 3;
    else if (b == 0xf0 && cont(1, 0x90) && cont(2) && cont(3)) n = 4;
    else if (b >= 0xf1 && b <= 0xf3 && cont(1) && cont(2) && cont(3)) n = 4;
    else if (b == 0xf4 && cont(1, 0x80, 0x8f) && cont(2) && cont(3)) n = 4;
    if (n == 0) {
      escape(b);
      ++i;
    } else {
      o.append(s.substr(i, n));
      i += n;
    }
  }
  return o;
}

}  // namespace polarcam
