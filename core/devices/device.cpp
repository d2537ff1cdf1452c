#include "core/devices/device.h"

namespace enact::devices {

ForceDevice::~ForceDevice() = default;
TactileDevice::~TactileDevice() = default;

const char* to_string(DeviceFault fault) {
  switch (fault) {
    case DeviceFault::watchdog: return "watchdog";
    case DeviceFault::clamped: return "clamped";
    case DeviceFault::nonfinite_command: return "nonfinite_command";
    case DeviceFault::workspace_limit: return "workspace_limit";
    case DeviceFault::device_error: return "device_error";
  }
  return "unknown";
}

}  // namespace enact::devices
