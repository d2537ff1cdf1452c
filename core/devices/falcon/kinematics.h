#pragma once
// Kinematics of the Novint Falcon, a delta (translational parallel) manipulator of the kind
// R. E. Stamper analysed ("A three degree of freedom parallel manipulator with only
// translational degrees of freedom", PhD thesis, University of Maryland, 1997). Geometry
// constants are libnifalcon's measurements (include/falcon/core/FalconGeometry.h, BSD;
// Kevin Ouellet), the encoder scale is libnifalcon's FalconKinematic::getTheta, the torque to
// motor command scale libnifalcon's FalconKinematicStamper::getForces. Equations derived here.
//
// Device frame (libnifalcon's): metres; x to the right and y up, seen from the front; z
// towards the user (the grip is in front of the base, z about 0.06 .. 0.17). Leg i sits at
// angle phi_i about z; in its own frame (u, v, w) = R(phi_i) p - (r, s, 0):
//   v = b cos t3 - f                          (the parallelogram "shin")
//   u = a cos t1 + L cos t2 - c,   w = a sin t1 + L sin t2,   L = d + e + b sin t3
// t1 is the motor's arm angle (from the encoder), t2 the knee, t3 the parallelogram's.
// Inverse: per leg in closed form (t3 from v; t1 from a quadratic in tan(t1/2); t2 from
// atan2). Forward: Newton's method on the three t1 with the analytic Jacobian.
//
// The enact frame (x right, y forward away from the user, z up; docs/devices.md) is the device frame
// turned and shifted so that the Falcon's workspace centre, (0, 0, 0.11) in the device frame
// (libnifalcon's sphere example centres its scene there), is the enact origin:
//   enact = (x_d, 0.11 - z_d, y_d),   device = (x_e, z_e, 0.11 - y_e).
#include <array>
#include <cstdint>

#include "core/math/vec3.h"

namespace enact::devices::falcon {

using math::Vec3;

// libnifalcon's FalconGeometry.h (metres, radians)
struct Geometry {
  double a = 0.060;        // hip to knee
  double b = 0.1025;       // parallelogram side
  double c = 0.014;        // shin joint to end-effector centre, u
  double d = 0.01125;      // shin to end-effector joint
  double e = 0.01125;      // knee to shin joint
  double f = -0.025;       // shin joint to end-effector centre, v
  double r = 0.037233758;  // origin to leg base, u
  double s = -0.027330909; // origin to leg base, v
  std::array<double, 3> phi{};  // leg angles about z: 90, -30, -150 degrees, each + 15
  Geometry();
};
const Geometry& geometry();

// the three legs' angles at one end-effector position
struct LegAngles {
  std::array<double, 3> t1{};  // motor arm angles (rad)
  std::array<double, 3> t2{};
  std::array<double, 3> t3{};
};

// row i: the gradient of leg i's arm angle t1_i with respect to the position (rad/m)
using Jacobian = std::array<Vec3, 3>;

// closed-form inverse kinematics of a device-frame position; false when out of reach
bool inverse(const Vec3& p_device, LegAngles& out) noexcept;
// d t1 / d p at the angles of a position (from inverse)
Jacobian angle_jacobian(const LegAngles& angles) noexcept;
// forward kinematics: the device-frame position whose arm angles are t1, by Newton's method
// from `guess` (the last position: a warm start); false when it did not converge
bool forward(const std::array<double, 3>& t1, const Vec3& guess, Vec3& out) noexcept;

// encoder counts <-> arm angle (rad): 320 slots x 4 edges per motor turn, a 14.25 mm shaft
// on a 110 mm capstan, count 0 at 35 degrees (after homing)
double angle_of(std::int16_t count) noexcept;
std::int16_t count_of(double angle_rad) noexcept;  // nearest, saturated to int16

// libnifalcon's motor command scale: command = -10000 per N m of joint torque
constexpr double kCommandPerNm = -10000.0;

// joint torques (N m) for a device-frame force at these angles: tau = (d p / d t1)^T F,
// i.e. solve J^T tau = F with J = angle_jacobian; false when J is singular
bool torques(const Jacobian& j, const Vec3& force_device_n, Vec3& tau_nm) noexcept;
// the force (device frame) that joint torques produce: F = J^T tau (the emulator's side)
Vec3 force_of(const Jacobian& j, const Vec3& tau_nm) noexcept;

// motor commands for joint torques, scaled down together (direction kept) when one would
// leave the int16 range
std::array<std::int16_t, 3> motor_commands(const Vec3& tau_nm) noexcept;
// joint torques from motor commands (the emulator's side)
Vec3 torques_of(const std::array<std::int16_t, 3>& motor) noexcept;

// the frames
constexpr double kCentreZ_m = 0.11;
constexpr Vec3 to_enact(const Vec3& d) { return {d.x, kCentreZ_m - d.z, d.y}; }
constexpr Vec3 to_device(const Vec3& e) { return {e.x, e.z, kCentreZ_m - e.y}; }
// directions (forces, velocities): the same turn, no shift
constexpr Vec3 direction_to_enact(const Vec3& d) { return {d.x, -d.z, d.y}; }
constexpr Vec3 direction_to_device(const Vec3& e) { return {e.x, e.z, -e.y}; }

}  // namespace enact::devices::falcon
