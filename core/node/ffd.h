#pragma once
// The force-feedback device driver of a distributed graph, and its clock master (enact-ffd).
// Each tick it reads the device, publishes DeviceState, waits (until just before the next
// tick) for the simulator's ForceCommand answering that sample, and writes the force. The
// safety layer's watchdog ramps the force to zero when answers stop coming.
#include <cstdint>
#include <memory>
#include <string>

#include "core/devices/device.h"
#include "core/node/host.h"
#include "core/rt/rt_setup.h"
#include "core/rt/scheduler.h"

namespace enact::node {

extern const NodeKind kFfd;

class Ffd {
 public:
  explicit Ffd(Host& host);  // the device made from its parameters
  ~Ffd();
  int run();

 private:
  struct Io;  // sockets, publishers, the loop's state: made by run()
  void open_hop();
  void plan_wait();
  void tick(std::int64_t now);
  bool next_answer(std::int64_t deadline_ns);
  void feel_pins();
  void publish_status();
  void say_summary();

  Host& host_;
  rt::SchedulerParams sched_;
  double spin_us_;
  std::string sim_node_, tactile_node_;
  double duration_s_;
  int observers_;
  rt::RtParams rtp_;
  std::unique_ptr<devices::ForceDevice> device_;
  bool local_hop_;
  std::unique_ptr<Io> io_;
};

}  // namespace enact::node
