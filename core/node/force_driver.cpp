#include "core/node/force_driver.h"

#include "core/devices/hand.h"
#include "core/graph/messages.h"
#include "core/node/components.h"

namespace enact::node {

ForceDriver::ForceDriver(std::unique_ptr<devices::ForceDevice> device, const std::string& node, const std::string& cut)
    : device_(std::move(device)), cuts_(node, cut) {}

devices::HandSource* ForceDriver::feeling_hand() const {
  devices::HandSource* hand = device_->simulated_hand();
  return hand && hand->feels_pins() ? hand : nullptr;
}

void ForceDriver::path(std::uint32_t faults, std::int64_t now_ns) { cuts_.update(graph::force_path_cut(graph::device_faults(faults)), now_ns); }

void ForceDriver::path_cut(bool cut, std::int64_t since_ns) {
  if (cut != cuts_.tripped()) cuts_.update(cut, since_ns);
}

std::string ForceDriver::summary() const { return cuts_.summary() + "; " + graph::safety_summary(*device_); }

}  // namespace enact::node
