#include "core/devices/device_profile.h"

namespace enact::devices {
namespace {

std::vector<DeviceProfile> profiles() {
  return {
      // ERGOS 3-DoF joystick as used by Khatchatourov et al. (2009): workspace 60 x 60 x 25 mm,
      // 200 N peak / 60 N continuous, 1.8 m/s, 60 m/s^2 peak, 1 um sensing resolution.
      // Moving mass and physical damping are not published: assumed values, to identify.
      // Force step limit: not published either; assumed 10 N/ms (the 200 N peak no sooner than
      // 20 ms from rest), above the steepest step of the scripted bridge walk at 5 kHz (1.6 N
      // in one 0.2 ms tick, 8 N/ms: tests/graph/colocated_test.cpp), so the limit does not
      // shape normal contacts; a jolt after a stall (0 to 200 N in 2 ms) is ten times steeper.
      {"ergos", {-0.030, -0.030, 0.0}, {0.030, 0.030, 0.025}, 200.0, 60.0, 1.8, 60.0, 1e-6, 0.2, 6.0, 10.0},
      // Novint Falcon-like: about 10 cm cube, about 9 N peak, 400 dpi (~64 um) resolution
      // (manufacturer's figures); speed, mass, damping and the force step limit assumed (2 N/ms:
      // the peak no sooner than 4.5 ms from rest).
      {"falcon", {-0.05, -0.05, -0.05}, {0.05, 0.05, 0.05}, 9.0, 4.0, 1.0, 30.0, 6.4e-5, 0.15, 0.5, 2.0},
  };
}

}  // namespace

std::optional<DeviceProfile> find_device_profile(const std::string& name) {
  for (auto& p : profiles()) {
    if (p.name == name) return p;
  }
  return std::nullopt;
}

std::vector<std::string> device_profile_names() {
  std::vector<std::string> out;
  for (const auto& p : profiles()) out.push_back(p.name);
  return out;
}

}  // namespace enact::devices
