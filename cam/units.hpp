#pragma once
// Quantities with units, as files and the command line give them ("7.62 cm", "1.52 cm/s", "3*pi/4 rad").
// The numeric part is an expression (muparser, with the constant pi); the unit part a product of known units
// with powers and '/', e.g. "kN/m^2", "V s/rad", "N m/A". Everything is converted to SI; angles are a base
// dimension of their own (rad) so that a length given where an angle belongs is caught.
#include <array>
#include <string>
#include <string_view>

namespace polarcam {

// Exponents of the base dimensions: length (m), mass (kg), time (s), current (A), angle (rad).
struct Dim {
  std::array<int, 5> e{0, 0, 0, 0, 0};
  constexpr bool operator==(const Dim&) const = default;
  constexpr Dim operator*(const Dim& o) const {
    Dim d;
    for (int i = 0; i < 5; ++i) d.e[i] = e[i] + o.e[i];
    return d;
  }
  constexpr Dim operator/(const Dim& o) const {
    Dim d;
    for (int i = 0; i < 5; ++i) d.e[i] = e[i] - o.e[i];
    return d;
  }
  constexpr Dim pow(int p) const {
    Dim d;
    for (int i = 0; i < 5; ++i) d.e[i] = e[i] * p;
    return d;
  }
};

namespace dim {
inline constexpr Dim none{};
inline constexpr Dim length{{1, 0, 0, 0, 0}};
inline constexpr Dim mass{{0, 1, 0, 0, 0}};
inline constexpr Dim time{{0, 0, 1, 0, 0}};
inline constexpr Dim current{{0, 0, 0, 1, 0}};
inline constexpr Dim angle{{0, 0, 0, 0, 1}};
inline constexpr Dim speed = length / time;
inline constexpr Dim acceleration = speed / time;
inline constexpr Dim frequency = none / time;
inline constexpr Dim area = length * length;
inline constexpr Dim force = mass * acceleration;
inline constexpr Dim torque = force * length;
inline constexpr Dim inertia = mass * area;
inline constexpr Dim voltage = mass * area / (time.pow(3) * current);
inline constexpr Dim resistance = voltage / current;
inline constexpr Dim inductance = resistance * time;
inline constexpr Dim pressure = force / area;
inline constexpr Dim angular_speed = angle / time;
}  // namespace dim

struct Quantity {
  double value = 0.0;  // SI
  Dim dim;
};

// Human name of a dimension for messages ("length (m)", "speed (m/s)", or the SI form).
std::string describe(const Dim& d);
// "a length (m)", "an acceleration (m/s^2)": the noun with its indefinite article.
std::string with_article(const std::string& noun);

// The largest magnitude of a quantity in SI units (and of a plain number given as a quantity): far beyond anything
// physical a machine or a job has, and small enough that the products and powers the models form stay finite.
inline constexpr double kQuantityLimit = 1e30;

// Parses "<number expression> [unit expression]". Throws InputError with a message that quotes the text.
Quantity parse_quantity(std::string_view text);

// Parses and checks the dimension. Angles also accept a plain number (radians).
double parse_quantity_as(std::string_view text, const Dim& expected);

// Evaluates a plain numeric expression ("3*pi/4", "1e-3"). Throws InputError.
double eval_number(std::string_view expr);

}  // namespace polarcam
