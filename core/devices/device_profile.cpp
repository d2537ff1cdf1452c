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
      // Force Dimension omega.3 (device: dhd). From the maker's data sheet as we recall it, TO
      // CHECK against forcedimension.com's current sheet: translation workspace a cylinder of
      // 160 mm diameter x 110 mm (here its bounding box about the DHD origin), 12.0 N
      // continuous force (no separate peak published: peak = continuous), resolution < 0.01 mm,
      // stiffness 14.5 N/mm. Speed, acceleration, moving mass, damping and the force step
      // limit (5 N/ms: the 12 N no sooner than 2.4 ms from rest) are assumed.
      {"omega3", {-0.080, -0.080, -0.055}, {0.080, 0.080, 0.055}, 12.0, 12.0, 1.0, 30.0, 1e-5, 0.2, 0.5, 5.0, 14500.0},
      // 3D Systems Touch (device: hd). From the maker's data sheet as we recall it, TO CHECK
      // against 3dsystems.com's current sheet: workspace 160 W x 120 H x 70 D mm (here a box
      // about the HD origin: W along x, D along y, H along z), 3.3 N maximum exertable force,
      // 0.88 N continuous, nominal resolution about 0.055 mm (450 dpi), stiffness 1.26 (x),
      // 2.31 (y), 1.02 (z) N/mm (the least here). Where the HD origin lies in the workspace,
      // speed, acceleration, moving mass, damping and the force step limit (1 N/ms: the 3.3 N
      // no sooner than 3.3 ms) are assumed.
      // Haply Inverse3 (device: inverse3). No figure here is from a data sheet we could read: all
      // TO CHECK against haply.co's current specifications. Workspace: a box of 240 x 160 x 160 mm
      // about enact's origin (origin_m in the service frame); peak and continuous force set low
      // on purpose (3 N) until checked, so the safety layer errs on the gentle side; the rest assumed.
      {"inverse3", {-0.120, -0.080, -0.080}, {0.120, 0.080, 0.080}, 3.0, 3.0, 1.0, 30.0, 1e-5, 0.2, 0.5, 1.0, 0.0},
      {"touch", {-0.080, -0.035, -0.060}, {0.080, 0.035, 0.060}, 3.3, 0.88, 1.0, 30.0, 5.5e-5, 0.05, 0.3, 1.0, 1020.0},
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
