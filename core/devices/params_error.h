#pragma once
// Internal to core/devices: refusing bad device parameters at configure time.
#include <string>

#include "core/config/yaml.h"

namespace enact::devices {

// "DEVICE: problem\n  fix: what to do", as config::Error
[[noreturn]] inline void refuse(const char* device, const std::string& problem, const std::string& fix) {
  throw config::Error(std::string(device) + ": " + problem + "\n  fix: " + fix);
}

}  // namespace enact::devices
