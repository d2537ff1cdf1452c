#include "core/devices/falcon/kinematics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace enact::devices::falcon {
namespace {

constexpr double kPi = std::numbers::pi;

// libnifalcon's FalconGeometry.h and FalconKinematic::getTheta: the encoder wheel's slots,
// the motor shaft and the arm's capstan diameters (m), the angle at count 0 (degrees)
constexpr double kWheelSlots = 320.0;
constexpr double kShaftDiameter_m = 0.01425;
constexpr double kCapstanDiameter_m = 0.110;
constexpr double kAngleAtZero_deg = 35.0;
// arm degrees per count: the shaft's travel per count over the capstan's per degree
constexpr double kDegPerCount = (kShaftDiameter_m * kPi / (kWheelSlots * 4.0)) / (kCapstanDiameter_m * kPi / 360.0);

// forward kinematics: Newton's method until the arm angles match within this (rad), or give up
constexpr double kAngleTolerance_rad = 1e-12;
constexpr int kMaxIterations = 30;

// a leg's frame coordinates of a device-frame position
Vec3 leg_frame(const Geometry& g, int leg, const Vec3& p) {
  const double cp = std::cos(g.phi[static_cast<std::size_t>(leg)]), sp = std::sin(g.phi[static_cast<std::size_t>(leg)]);
  return {cp * p.x + sp * p.y - g.r, -sp * p.x + cp * p.y - g.s, p.z};
}

// solve A x = y for a 3x3 A given by rows (Cramer's rule); false when singular
bool solve(const std::array<Vec3, 3>& rows, const Vec3& y, Vec3& x) {
  const Vec3 &r0 = rows[0], &r1 = rows[1], &r2 = rows[2];
  const Vec3 c12{r1.y * r2.z - r1.z * r2.y, r1.z * r2.x - r1.x * r2.z, r1.x * r2.y - r1.y * r2.x};
  const double det = math::dot(r0, c12);
  if (!std::isfinite(det) || std::abs(det) < 1e-300) return false;
  // x = adj(A) y / det, with adj's columns the cross products of the rows
  const Vec3 c20{r2.y * r0.z - r2.z * r0.y, r2.z * r0.x - r2.x * r0.z, r2.x * r0.y - r2.y * r0.x};
  const Vec3 c01{r0.y * r1.z - r0.z * r1.y, r0.z * r1.x - r0.x * r1.z, r0.x * r1.y - r0.y * r1.x};
  x = (c12 * y.x + c20 * y.y + c01 * y.z) * (1.0 / det);
  return math::finite(x);
}

// the transpose of rows: A^T
std::array<Vec3, 3> transposed(const std::array<Vec3, 3>& m) {
  return {Vec3{m[0].x, m[1].x, m[2].x}, Vec3{m[0].y, m[1].y, m[2].y}, Vec3{m[0].z, m[1].z, m[2].z}};
}

}  // namespace

Geometry::Geometry() {
  // 90, -30 and -150 degrees, each turned by 15 degrees (the axes' offset from the desk plane)
  const double offset = kPi / 12.0;
  phi = {kPi / 2.0 + offset, -kPi / 6.0 + offset, -5.0 * kPi / 6.0 + offset};
}

const Geometry& geometry() {
  static const Geometry g;
  return g;
}

bool inverse(const Vec3& p, LegAngles& out) noexcept {
  const Geometry& g = geometry();
  for (int leg = 0; leg < 3; ++leg) {
    const auto i = static_cast<std::size_t>(leg);
    const Vec3 q = leg_frame(g, leg, p);
    // the parallelogram from v
    const double cos_t3 = (q.y + g.f) / g.b;
    if (!(std::abs(cos_t3) <= 1.0)) return false;
    const double t3 = std::acos(cos_t3);
    const double len = g.d + g.e + g.b * std::sin(t3);
    // the arm: a (u + c) cos t1 + a w sin t1 = K / 2, the root of the Falcon's configuration
    const double uc = q.x + g.c;
    const double k = uc * uc + q.z * q.z + g.a * g.a - len * len;
    const double reach = g.a * std::hypot(uc, q.z);
    const double ratio = k / (2.0 * reach);
    if (!(std::abs(ratio) <= 1.0)) return false;
    const double t1 = std::atan2(q.z, uc) - std::acos(ratio);
    // the knee: the rest of the way to the shin joint
    const double t2 = std::atan2(q.z - g.a * std::sin(t1), uc - g.a * std::cos(t1));
    out.t1[i] = t1;
    out.t2[i] = t2;
    out.t3[i] = t3;
  }
  return true;
}

Jacobian angle_jacobian(const LegAngles& angles) noexcept {
  // differentiating the leg equations and eliminating d t2 and d t3:
  //   a sin(t2 - t1) d t1 = cos t2 du + sin t2 dw + cot t3 dv
  const Geometry& g = geometry();
  Jacobian j;
  for (int leg = 0; leg < 3; ++leg) {
    const auto i = static_cast<std::size_t>(leg);
    const double cp = std::cos(g.phi[i]), sp = std::sin(g.phi[i]);
    const double ct2 = std::cos(angles.t2[i]), st2 = std::sin(angles.t2[i]);
    const double cot3 = std::cos(angles.t3[i]) / std::sin(angles.t3[i]);
    const double den = g.a * std::sin(angles.t2[i] - angles.t1[i]);
    // du/dp = (cp, sp, 0), dv/dp = (-sp, cp, 0), dw/dp = (0, 0, 1)
    j[i] = Vec3{ct2 * cp - cot3 * sp, ct2 * sp + cot3 * cp, st2} * (1.0 / den);
  }
  return j;
}

bool forward(const std::array<double, 3>& t1, const Vec3& guess, Vec3& out) noexcept {
  Vec3 p = guess;
  LegAngles at;
  if (!inverse(p, at)) {
    p = {0.0, 0.0, kCentreZ_m};
    if (!inverse(p, at)) return false;
  }
  auto miss_at = [&](const LegAngles& a) { return Vec3{t1[0] - a.t1[0], t1[1] - a.t1[1], t1[2] - a.t1[2]}; };
  Vec3 miss = miss_at(at);
  for (int it = 0; it < kMaxIterations; ++it) {
    if (std::max({std::abs(miss.x), std::abs(miss.y), std::abs(miss.z)}) < kAngleTolerance_rad) {
      out = p;
      return true;
    }
    // the Newton step, halved until it lands in reach with a smaller miss (backtracking)
    Vec3 step;
    if (!solve(angle_jacobian(at), miss, step)) return false;
    bool moved = false;
    for (int halve = 0; halve < 40 && !moved; ++halve, step *= 0.5) {
      LegAngles next;
      if (!inverse(p + step, next)) continue;
      const Vec3 next_miss = miss_at(next);
      if (math::norm(next_miss) >= math::norm(miss)) continue;
      p += step;
      at = next;
      miss = next_miss;
      moved = true;
    }
    if (!moved) return false;
  }
  return false;
}

double angle_of(std::int16_t count) noexcept { return (static_cast<double>(count) * kDegPerCount + kAngleAtZero_deg) * kPi / 180.0; }

std::int16_t count_of(double angle_rad) noexcept {
  const double c = std::round((angle_rad * 180.0 / kPi - kAngleAtZero_deg) / kDegPerCount);
  return static_cast<std::int16_t>(std::clamp(c, -32768.0, 32767.0));
}

bool torques(const Jacobian& j, const Vec3& force_device_n, Vec3& tau_nm) noexcept {
  // tau = (dp/dt1)^T F = (J^-1)^T F: solve J^T tau = F
  return solve(transposed(j), force_device_n, tau_nm);
}

Vec3 force_of(const Jacobian& j, const Vec3& tau_nm) noexcept {
  // F = J^T tau
  return j[0] * tau_nm.x + j[1] * tau_nm.y + j[2] * tau_nm.z;
}

std::array<std::int16_t, 3> motor_commands(const Vec3& tau_nm) noexcept {
  const Vec3 raw = tau_nm * kCommandPerNm;
  const double biggest = std::max({std::abs(raw.x), std::abs(raw.y), std::abs(raw.z)});
  constexpr double kMax = std::numeric_limits<std::int16_t>::max();
  const Vec3 scaled = biggest > kMax ? raw * (kMax / biggest) : raw;
  return {static_cast<std::int16_t>(std::lround(scaled.x)), static_cast<std::int16_t>(std::lround(scaled.y)),
          static_cast<std::int16_t>(std::lround(scaled.z))};
}

Vec3 torques_of(const std::array<std::int16_t, 3>& motor) noexcept {
  return Vec3{static_cast<double>(motor[0]), static_cast<double>(motor[1]), static_cast<double>(motor[2])} * (1.0 / kCommandPerNm);
}

}  // namespace enact::devices::falcon
