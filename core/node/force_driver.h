#pragma once
// The force-feedback device's driver: one component whichever host runs it. enact-ffd
// (node/ffd.h) wires it to the bus and is the graph's clock master; the co-located container
// (node/colocated.h) reads and writes its device in the tick. Both say each cut of the force
// path once (begun, ended after how long) and print its summary line when it ends.
#include <cstdint>
#include <memory>
#include <string>

#include "core/devices/device.h"
#include "core/graph/watchdog_log.h"

namespace enact::node {

class ForceDriver {
 public:
  // drives `device` (configured: graph::make_force_device, in its safety layer); `node` names
  // its lines, `cut` says what a cut of the force path does in this host
  ForceDriver(std::unique_ptr<devices::ForceDevice> device, const std::string& node, const std::string& cut);

  devices::ForceDevice& device() { return *device_; }
  // a simulated hand that feels the pins (a virtual subject), nullptr for none
  devices::HandSource* feeling_hand() const;

  // the force path at now_ns, from a sample's device faults (the device's watchdog or an
  // error bit cut it): a change begins or ends an episode and says so (it prints)
  void path(std::uint32_t faults, std::int64_t now_ns);
  // the same from a tick's observation: whether it is cut, and since when (a change only)
  void path_cut(bool cut, std::int64_t since_ns);
  const graph::WatchdogLog& cuts() const { return cuts_; }

  // "<episodes>; <the safety layer>; force at exit: ...": the line both hosts print at the end
  std::string summary() const;

 private:
  std::unique_ptr<devices::ForceDevice> device_;
  graph::WatchdogLog cuts_;
};

}  // namespace enact::node
