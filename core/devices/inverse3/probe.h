#pragma once
// Whether the Haply Inverse Service runs on this machine and lists a usable Inverse3, for
// `enact devices`: its inventory, each device with its id and state, or what is missing.
#include <string>

#include "core/devices/vendor/probe.h"

namespace enact::devices::inverse3 {

vendor::Presence probe_inverse3(const std::string& host, int port, double timeout_s);

}  // namespace enact::devices::inverse3
