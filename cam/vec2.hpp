#pragma once
// Plain 2-D vector used by the geometry code (SI units, metres). Eigen is used where linear algebra is needed;
// this small value type keeps the hot evaluation paths free of expression templates.
#include <cmath>

namespace polarcam {

struct Vec2 {
  double x = 0.0, y = 0.0;
  constexpr Vec2 operator+(Vec2 o) const { return {x + o.x, y + o.y}; }
  constexpr Vec2 operator-(Vec2 o) const { return {x - o.x, y - o.y}; }
  constexpr Vec2 operator-() const { return {-x, -y}; }
  constexpr Vec2 operator*(double k) const { return {x * k, y * k}; }
  constexpr Vec2 operator/(double k) const { return {x / k, y / k}; }
  constexpr Vec2& operator+=(Vec2 o) {
    x += o.x;
    y += o.y;
    return *this;
  }
  constexpr bool operator==(const Vec2&) const = default;
};
constexpr Vec2 operator*(double k, Vec2 v) { return {k * v.x, k * v.y}; }
constexpr double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
constexpr double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
inline double norm(Vec2 a) { return std::hypot(a.x, a.y); }
constexpr Vec2 perp(Vec2 a) { return {-a.y, a.x}; }  // rotated +90 degrees (left normal direction)

}  // namespace polarcam
