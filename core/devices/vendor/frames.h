#pragma once
// The vendors' frames and units, turned into enact's (x right, y forward away from the user,
// z up; metres, newtons; docs/devices.md). Each is a proper rotation (no mirror) about the device's
// own origin; positions, velocities and forces turn alike.
//
// Force Dimension DHD (dhdGetPosition, dhdSetForce): metres and newtons; x towards the
// operator, y to the operator's right, z up (Force Dimension SDK documentation, "coordinate
// system"; to check on a device).
//
// OpenHaptics HD (HD_CURRENT_POSITION / VELOCITY / FORCE): millimetres, mm/s and newtons;
// x to the right, y up, z towards the user (OpenHaptics Programmer's Guide, "device
// coordinates"; to check on a device).
#include "core/math/vec3.h"

namespace enact::devices::vendor {

constexpr math::Vec3 dhd_to_enact(const math::Vec3& d) { return {d.y, -d.x, d.z}; }
constexpr math::Vec3 enact_to_dhd(const math::Vec3& e) { return {-e.y, e.x, e.z}; }

constexpr double kMetresPerMillimetre = 1e-3;
// an HD position (mm) or velocity (mm/s) in enact units (m, m/s) and frame
constexpr math::Vec3 hd_mm_to_enact_m(const math::Vec3& h) {
  return {h.x * kMetresPerMillimetre, -h.z * kMetresPerMillimetre, h.y * kMetresPerMillimetre};
}
// an enact force (N) in the HD frame (N)
constexpr math::Vec3 enact_to_hd_force(const math::Vec3& e) { return {e.x, e.z, -e.y}; }

}  // namespace enact::devices::vendor
