#pragma once
// Internal to core/devices: refusing bad device parameters at configure time.
#include <string>

#include "core/config/format.h"
#include "core/config/yaml.h"

namespace enact::devices {

// "DEVICE: problem\n  fix: what to do", as config::Error
[[noreturn]] inline void refuse(const char* device, const std::string& problem, const std::string& fix) {
  throw config::Error(std::string(device) + ": " + problem + "\n  fix: " + fix);
}

// refuse param `name` (its value) unless ok, saying the range it must be in
inline void require(bool ok, const char* device, const char* name, double value, const std::string& range) {
  if (!ok) refuse(device, std::string(name) + " is " + config::number(value), std::string("set ") + name + " in " + range);
}

}  // namespace enact::devices
