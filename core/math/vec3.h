#pragma once
// Small fixed-size vector and rotation types shared by the physics engine
// and the devices (header only, no heap).
#include <cmath>
#include <limits>

namespace enact::math {

struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;

  constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
  friend constexpr Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
  friend constexpr Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
  friend constexpr Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
  friend constexpr Vec3 operator*(Vec3 a, double s) { return a *= s; }
  friend constexpr Vec3 operator*(double s, Vec3 a) { return a *= s; }
  friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// x, y or z (axis 0, 1, 2)
constexpr double component(const Vec3& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }
inline bool finite(const Vec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

// rotation matrix stored by columns: the rotated frame's axes in world coordinates
struct Mat3 {
  Vec3 c0{1, 0, 0};
  Vec3 c1{0, 1, 0};
  Vec3 c2{0, 0, 1};

  // local -> world
  constexpr Vec3 operator*(const Vec3& v) const { return c0 * v.x + c1 * v.y + c2 * v.z; }
  // transpose times v: world -> local
  constexpr Vec3 transpose_times(const Vec3& v) const { return {dot(c0, v), dot(c1, v), dot(c2, v)}; }
  constexpr const Vec3& column(int i) const { return i == 0 ? c0 : i == 1 ? c1 : c2; }
};

// rotation from roll (about x), pitch (about y), yaw (about z), applied in that order: R = Rz Ry Rx
inline Mat3 rotation_rpy(double roll_rad, double pitch_rad, double yaw_rad) {
  const double cr = std::cos(roll_rad), sr = std::sin(roll_rad);
  const double cp = std::cos(pitch_rad), sp = std::sin(pitch_rad);
  const double cy = std::cos(yaw_rad), sy = std::sin(yaw_rad);
  return {{cy * cp, sy * cp, -sp},
          {cy * sp * sr - sy * cr, sy * sp * sr + cy * cr, cp * sr},
          {cy * sp * cr + sy * sr, sy * sp * cr - cy * sr, cp * cr}};
}

}  // namespace enact::math
