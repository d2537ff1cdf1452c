#pragma once
// Device profiles: what a force-feedback device can do, for safety limits, the simulated
// device (later) and the passivity bound. Figures and their sources are in the .cpp.
#include <optional>
#include <string>
#include <vector>

#include "core/math/vec3.h"

namespace enact::devices {

struct DeviceProfile {
  std::string name;
  math::Vec3 workspace_min_m;
  math::Vec3 workspace_max_m;
  double peak_force_n = 0.0;
  double continuous_force_n = 0.0;
  double max_speed_m_per_s = 0.0;
  double max_acceleration_m_per_s2 = 0.0;
  double resolution_m = 0.0;
  double moving_mass_kg = 0.0;       // assumed; identify your device
  double damping_n_s_per_m = 0.0;    // physical damping b (passivity bound); assumed
  // the largest change of the commanded force allowed within one millisecond (any shorter
  // interval: proportionally less): the safety layer's last-line slew limit; assumed
  double max_force_step_n_per_ms = 0.0;
  // the largest stiffness the maker rates the device to render (0: not published)
  double max_stiffness_n_per_m = 0.0;
};

std::optional<DeviceProfile> find_device_profile(const std::string& name);
std::vector<std::string> device_profile_names();

}  // namespace enact::devices
