#pragma once
// The tactile display driver of a distributed graph (enact-tactile): node::TactileDriver
// (node/tactile_driver.h) on the bus. It applies each TactileFrame to the pins and publishes
// what they physically show (after the cells' rise time) on tactile/shown. On stop it lowers
// every pin, and when frames stop coming for longer than watchdog_s (the simulator hangs or
// died) too, until they come again.
#include <memory>
#include <string>

#include "core/node/host.h"
#include "core/node/tactile_driver.h"
#include "core/params/device_config.h"

namespace enact::node {

extern const NodeKind kTactile;

class Tactile {
 public:
  explicit Tactile(Host& host);  // the device made from its parameters
  ~Tactile();
  // its lifecycle in the process host (host_main)
  void open_ports();
  void activate();
  void run();
  int deactivate();

 private:
  struct Io;  // sockets, publishers and messages: made by open_ports()
  void apply(std::int64_t now);
  void publish_shown(std::int64_t now);
  void publish_status(std::int64_t now);
  void run_real();
  void run_simulated();

  Host& host_;
  std::unique_ptr<devices::TactileDevice> device_;
  TactileDriver driver_;
  graph::TactileNodeConfig config_;
  std::unique_ptr<Io> io_;
};

}  // namespace enact::node
