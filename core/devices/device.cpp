#include "core/devices/device.h"

#include <algorithm>

namespace enact::devices {

ForceDevice::~ForceDevice() = default;
TactileDevice::~TactileDevice() = default;

double PinMotion::level(int pin, std::int64_t now_ns) const noexcept {
  const Stroke& s = strokes[static_cast<std::size_t>(pin)];
  const double moved = static_cast<double>(std::max<std::int64_t>(0, now_ns - s.from_ns)) / rise_ns;
  return (targets >> pin) & 1u ? std::min(1.0, s.from_level + moved) : std::max(0.0, s.from_level - moved);
}

void PinMotion::set_targets(std::int64_t now_ns, std::uint32_t pins, int count) noexcept {
  const std::uint32_t changed = pins ^ targets;
  for (int i = 0; i < count; ++i) {
    if (((changed >> i) & 1u) == 0) continue;
    strokes[static_cast<std::size_t>(i)] = {level(i, now_ns), now_ns};
  }
  targets = pins;
}

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
