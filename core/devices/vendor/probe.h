#pragma once
// Whether a vendor SDK's device is usable on this machine, for `enact devices`: the library
// loads and has the functions enact binds, and a device answers. Each result says what is
// missing (the library, the device, its calibration is left to configure) and the fix.
#include <string>

namespace enact::devices::vendor {

struct Presence {
  bool present = false;
  std::string report;  // one or more lines, each ending in a newline
};

// Force Dimension: load `library`, count the devices (dhdGetDeviceCount)
Presence probe_dhd(const std::string& library);
// OpenHaptics: load `library`, open the device `device_name` (empty: the default) and close it
Presence probe_hd(const std::string& library, const std::string& device_name);

}  // namespace enact::devices::vendor
