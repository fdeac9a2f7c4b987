#include "machine/player/scaling.hpp"

#include <cctype>

#include "cam/error.hpp"
#include "machine/player/int128.hpp"

namespace polarcam {
namespace {

constexpr int64_t kMaxPart = int64_t{1} << 31;

// Decimal "123.456" -> num/den, or nothing when it is not a plain positive decimal.
bool parse_decimal(const std::string& s, int64_t& num, int64_t& den) {
  if (s.empty()) return false;
  num = 0;
  den = 1;
  bool dot = false, digit = false;
  for (char c : s) {
    if (c == '.') {
      if (dot) return false;
      dot = true;
      continue;
    }
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    digit = true;
    if (num > kMaxPart * 10 || den > kMaxPart) return false;
    num = num * 10 + (c - '0');
    if (dot) den *= 10;
  }
  return digit;
}

}  // namespace

Ratio parse_ratio(const std::string& text, const std::string& what) {
  auto bad = [&](const std::string& why) -> Ratio {
    throw InputError(what + " '" + text + "': " + why);
  };
  std::string a = text, b = "1";
  if (auto slash = text.find('/'); slash != std::string::npos) {
    a = text.substr(0, slash);
    b = text.substr(slash + 1);
  }
  int64_t an, ad, bn, bd;
  if (!parse_decimal(a, an, ad) || !parse_decimal(b, bn, bd))
    return bad("expected a positive decimal number, or a ratio of two, such as 2, 0.5 or 3/2 (no exponent, sign or unit)");
  // (an/ad) / (bn/bd)
  if (bn == 0) return bad("has a zero denominator");
  if (an == 0) return bad("must be greater than zero");
  i128 num = static_cast<i128>(an) * bd, den = static_cast<i128>(ad) * bn;
  // reduce with 128-bit Euclid
  i128 x = num, y = den;
  while (y != 0) {
    i128 t = x % y;
    x = y;
    y = t;
  }
  num /= x;
  den /= x;
  if (num >= kMaxPart || den >= kMaxPart) return bad("has too many digits (numerator and denominator must fit 31 bits)");
  return Ratio{static_cast<int64_t>(num), static_cast<int64_t>(den)};
}

std::string to_string(const Ratio& r) {
  return r.den == 1 ? std::to_string(r.num) : std::to_string(r.num) + "/" + std::to_string(r.den);
}

int64_t scaled_radial_index(int64_t n, const Ratio& s) {
  i128 a = 2 * static_cast<i128>(n) * s.num + s.den, b = 2 * static_cast<i128>(s.den);
  i128 q = a / b;
  if ((a % b != 0) && ((a < 0) != (b < 0))) --q;  // floor
  constexpr i128 kMax = i128{1} << 62;  // the machine's index, its sums and differences stay within 64 bits
  if (q > kMax || q < -kMax)
    throw InputError("the size scale " + to_string(s) + " takes radial node " + std::to_string(n) +
                     " beyond 2^62 steps from the pole: use a smaller size scale");
  return static_cast<int64_t>(q);
}

}  // namespace polarcam
