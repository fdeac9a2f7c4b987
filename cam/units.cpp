#include "cam/units.hpp"

#include <muParser.h>

#include <cctype>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "cam/error.hpp"
#include "cam/format.hpp"

namespace polarcam {
namespace {

struct UnitDef {
  double factor;
  Dim dim;
};

const std::unordered_map<std::string, UnitDef>& unit_table() {
  using namespace dim;
  static const std::unordered_map<std::string, UnitDef> table = [] {
    constexpr double pi = std::numbers::pi;
    constexpr double inch = 0.0254, foot = 0.3048, lbm = 0.45359237, g0 = 9.80665;
    std::unordered_map<std::string, UnitDef> t{
        // length
        {"m", {1.0, length}}, {"km", {1e3, length}}, {"cm", {1e-2, length}}, {"mm", {1e-3, length}},
        {"um", {1e-6, length}}, {"µm", {1e-6, length}}, {"nm", {1e-9, length}}, {"in", {inch, length}},
        {"inch", {inch, length}}, {"ft", {foot, length}}, {"mil", {inch * 1e-3, length}},
        {"thou", {inch * 1e-3, length}},
        // mass
        {"kg", {1.0, mass}}, {"g", {1e-3, mass}}, {"mg", {1e-6, mass}}, {"lb", {lbm, mass}},
        {"slug", {lbm * g0 / foot, mass}}, {"oz", {lbm / 16.0, mass}},
        // time
        {"s", {1.0, time}}, {"ms", {1e-3, time}}, {"us", {1e-6, time}}, {"µs", {1e-6, time}},
        {"ns", {1e-9, time}}, {"min", {60.0, time}}, {"h", {3600.0, time}},
        // current
        {"A", {1.0, current}}, {"mA", {1e-3, current}},
        // angle
        {"rad", {1.0, angle}}, {"mrad", {1e-3, angle}}, {"urad", {1e-6, angle}}, {"deg", {pi / 180.0, angle}},
        {"rev", {2.0 * pi, angle}}, {"turn", {2.0 * pi, angle}}, {"arcmin", {pi / 10800.0, angle}},
        {"arcsec", {pi / 648000.0, angle}},
        // frequency and rotational speed
        {"Hz", {1.0, frequency}}, {"kHz", {1e3, frequency}}, {"MHz", {1e6, frequency}},
        {"rpm", {2.0 * pi / 60.0, angular_speed}},
        // force, torque, pressure, energy, power
        {"N", {1.0, force}}, {"kN", {1e3, force}}, {"mN", {1e-3, force}}, {"lbf", {lbm * g0, force}},
        {"ozf", {lbm * g0 / 16.0, force}}, {"kgf", {g0, force}}, {"Pa", {1.0, pressure}},
        {"kPa", {1e3, pressure}}, {"MPa", {1e6, pressure}}, {"GPa", {1e9, pressure}},
        {"psi", {lbm * g0 / (inch * inch), pressure}}, {"J", {1.0, torque}}, {"W", {1.0, torque / time}},
        // electrical
        {"V", {1.0, voltage}}, {"mV", {1e-3, voltage}}, {"ohm", {1.0, resistance}}, {"Ohm", {1.0, resistance}},
        {"Ω", {1.0, resistance}}, {"H", {1.0, inductance}}, {"mH", {1e-3, inductance}},
        {"uH", {1e-6, inductance}}, {"µH", {1e-6, inductance}},
    };
    return t;
  }();
  return table;
}

bool is_ident_start(unsigned char c) { return std::isalpha(c) || c == '_' || c >= 0x80; }
bool is_ident_char(unsigned char c) { return std::isalnum(c) || c == '_' || c >= 0x80; }

std::string trim(std::string_view s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return std::string(s.substr(b, e - b));
}

// Recursive-descent parser of unit expressions: product := factor { ('*' | ' ' | '/') factor };
// factor := ident ['^' int] | '(' product ')' ['^' int]. '/' divides by the single factor that follows it.
class UnitParser {
 public:
  UnitParser(std::string_view text, std::string_view whole) : s_(text), whole_(whole) {}

  UnitDef parse() {
    UnitDef u{1.0, dim::none};
    skip_ws();
    if (pos_ < s_.size() && s_[pos_] == '/') {  // "1/s" split as "1" and "/s"
      ++pos_;
      UnitDef f = factor();
      u = UnitDef{1.0 / f.factor, dim::none / f.dim};
    } else {
      u = factor();
    }
    product_tail(u, /*inside_paren=*/false);
    return u;
  }

 private:
  void product_tail(UnitDef& u, bool inside_paren) {
    for (;;) {
      skip_ws();
      if (pos_ >= s_.size()) {
        if (inside_paren) fail("missing ')'");
        return;
      }
      char c = s_[pos_];
      if (c == ')') {
        if (!inside_paren) fail("unbalanced ')'");
        return;
      }
      if (c == '/') {
        ++pos_;
        UnitDef f = factor();
        u.factor /= f.factor;
        u.dim = u.dim / f.dim;
      } else {
        if (c == '*' || c == '.') ++pos_;
        UnitDef f = factor();
        u.factor *= f.factor;
        u.dim = u.dim * f.dim;
      }
    }
  }

  UnitDef factor() {
    skip_ws();
    if (pos_ >= s_.size()) fail("a unit is missing");
    UnitDef u;
    if (s_[pos_] == '(') {
      ++pos_;
      u = factor();
      product_tail(u, true);
      ++pos_;  // ')'
    } else if (is_ident_start(static_cast<unsigned char>(s_[pos_]))) {
      size_t b = pos_;
      while (pos_ < s_.size() && is_ident_char(static_cast<unsigned char>(s_[pos_]))) ++pos_;
      std::string name(s_.substr(b, pos_ - b));
      auto it = unit_table().find(name);
      if (it == unit_table().end()) fail("unknown unit '" + name + "'");
      u = it->second;
    } else {
      fail(std::string("unexpected '") + s_[pos_] + "'");
    }
    skip_ws();
    if (pos_ < s_.size() && s_[pos_] == '^') {
      ++pos_;
      skip_ws();
      size_t b = pos_;
      if (pos_ < s_.size() && (s_[pos_] == '-' || s_[pos_] == '+')) ++pos_;
      while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
      std::string p(s_.substr(b, pos_ - b));
      if (p.empty() || p == "-" || p == "+") fail("a power must be an integer");
      const size_t digits = p.size() - (std::isdigit(static_cast<unsigned char>(p[0])) ? 0 : 1);
      const int n = digits > 2 ? 100 : std::stoi(p);  // beyond std::stoi's range otherwise (found by fuzz_units)
      if (n < -12 || n > 12) fail("the power '" + p + "' is not an integer from -12 to 12");
      u.factor = std::pow(u.factor, n);
      u.dim = u.dim.pow(n);
      for (int e : u.dim.e)  // powers of powers: exponents stay far from int's range
        if (e < -1000 || e > 1000) fail("the powers of a unit multiply beyond 1000");
    }
    return u;
  }

  void skip_ws() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError("'" + std::string(whole_) + "': " + why);
  }

  std::string_view s_;
  std::string_view whole_;
  size_t pos_ = 0;
};

// Splits "3*pi/4 rad" into "3*pi/4" and "rad": the numeric part ends with the last number, 'pi' or ')' before
// the first identifier that is not 'pi'.
void split_quantity(std::string_view text, std::string& number, std::string& unit) {
  size_t i = 0, end_numeric = 0;
  while (i < text.size()) {
    unsigned char c = static_cast<unsigned char>(text[i]);
    if (std::isdigit(c) || (c == '.' && i + 1 < text.size() && std::isdigit(static_cast<unsigned char>(text[i + 1])))) {
      // number with optional exponent
      while (i < text.size() && (std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '.')) ++i;
      if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        size_t j = i + 1;
        if (j < text.size() && (text[j] == '+' || text[j] == '-')) ++j;
        if (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j]))) {
          i = j;
          while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
        }
      }
      end_numeric = i;
    } else if (is_ident_start(c)) {
      size_t b = i;
      while (i < text.size() && is_ident_char(static_cast<unsigned char>(text[i]))) ++i;
      std::string_view id = text.substr(b, i - b);
      if (id == "pi" || id == "sqrt" || id == "sin" || id == "cos" || id == "tan" || id == "atan" || id == "exp" ||
          id == "log" || id == "ln") {
        end_numeric = i;
        continue;
      }
      break;
    } else if (c == ')') {
      ++i;
      end_numeric = i;
    } else {
      ++i;
    }
  }
  number = trim(text.substr(0, end_numeric));
  unit = trim(text.substr(end_numeric));
}

}  // namespace

double eval_number(std::string_view expr) {
  std::string e = trim(expr);
  if (e.empty()) throw InputError("'" + std::string(expr) + "': a number is missing");
  try {
    mu::Parser p;
    p.DefineConst("pi", std::numbers::pi);
    p.SetExpr(e);
    double v = p.Eval();
    if (!std::isfinite(v)) throw InputError("'" + std::string(expr) + "' is not a finite number");
    return v;
  } catch (mu::Parser::exception_type& ex) {
    throw InputError("'" + std::string(expr) + "' is not a number: " + ex.GetMsg());
  }
}

Quantity parse_quantity(std::string_view text) {
  std::string number, unit;
  split_quantity(text, number, unit);
  if (number.empty()) throw InputError("'" + std::string(text) + "': a number is missing");
  double v = eval_number(number);
  const UnitDef u = unit.empty() ? UnitDef{1.0, dim::none} : UnitParser(unit, text).parse();
  const double si = v * u.factor;
  if (!(std::abs(si) <= kQuantityLimit))
    throw InputError("'" + std::string(text) + "' is too large: " +
                     (unit.empty() ? "a number must be within " + significant(kQuantityLimit, 3)
                                   : "a quantity must be within " + significant(kQuantityLimit, 3) + " in SI units (" +
                                         describe(u.dim) + ")"));
  return {si, u.dim};
}

double parse_quantity_as(std::string_view text, const Dim& expected) {
  Quantity q = parse_quantity(text);
  if (q.dim == expected) return q.value;
  if (expected == dim::angle && q.dim == dim::none) return q.value;
  // rev/length style (k_R) given where angle/length is expected works through the angle dimension already.
  throw InputError("'" + std::string(text) + "' is " + with_article(describe(q.dim)) + ", expected " +
                   with_article(describe(expected)));
}

std::string with_article(const std::string& noun) {
  const bool vowel = !noun.empty() && std::string_view("aeiou").find(noun.front()) != std::string_view::npos;
  return (vowel ? "an " : "a ") + noun;
}

std::string describe(const Dim& d) {
  struct Named {
    Dim d;
    const char* name;
  };
  static const Named names[] = {
      {dim::none, "plain number"}, {dim::length, "length (m)"}, {dim::mass, "mass (kg)"},
      {dim::time, "time (s)"}, {dim::current, "current (A)"}, {dim::angle, "angle (rad)"},
      {dim::speed, "speed (m/s)"}, {dim::acceleration, "acceleration (m/s^2)"},
      {dim::frequency, "frequency (Hz)"}, {dim::area, "area (m^2)"}, {dim::force, "force (N)"},
      {dim::torque, "torque (N m)"}, {dim::inertia, "moment of inertia (kg m^2)"},
      {dim::voltage, "voltage (V)"}, {dim::resistance, "resistance (ohm)"}, {dim::inductance, "inductance (H)"},
      {dim::pressure, "pressure (Pa)"}, {dim::angular_speed, "angular speed (rad/s)"},
      {dim::force / dim::length, "stiffness (N/m)"}, {dim::force * dim::time / dim::length, "damping (N s/m)"},
      {dim::force / (dim::length * dim::length * dim::length), "force per volume (N/m^3)"},
  };
  for (const auto& n : names)
    if (n.d == d) return n.name;
  static const char* base[] = {"m", "kg", "s", "A", "rad"};
  std::string s = "quantity in ";
  bool first = true;
  for (int i = 0; i < 5; ++i) {
    if (d.e[i] == 0) continue;
    if (!first) s += " ";
    s += base[i];
    if (d.e[i] != 1) {
      s += '^';
      s += std::to_string(d.e[i]);
    }
    first = false;
  }
  return s;
}

}  // namespace polarcam
