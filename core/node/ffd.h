#pragma once
// The force-feedback device driver of a distributed graph, and its clock master (enact-ffd).
// Each tick it reads the device, publishes DeviceState, waits (until its loop spins to the
// next tick) for the simulator's ForceCommand answering that sample, and writes the force;
// an answer that came while it spun is taken at the next tick, before its sample. The
// safety layer's watchdog ramps the force to zero when answers stop coming.
#include <cstdint>
#include <memory>
#include <string>

#include "core/node/force_driver.h"
#include "core/node/host.h"
#include "core/params/device_config.h"
#include "core/rt/rt_setup.h"
#include "core/rt/scheduler.h"

namespace enact::node {

extern const NodeKind kFfd;

class Ffd {
 public:
  explicit Ffd(Host& host);  // the device made from its parameters
  ~Ffd();
  // its lifecycle in the process host (host_main)
  void open_ports();
  void activate();
  void run();
  int deactivate();

 private:
  struct Io;  // sockets, publishers, the loop's state: made by open_ports()
  void open_hop();
  void plan_wait();
  bool apply_answer(std::int64_t now);
  void tick(std::int64_t now);
  bool next_answer(std::int64_t deadline_ns);
  bool await_answer(std::int64_t answer_by);
  bool await_shown(std::uint64_t due);
  void feel_pins(std::int64_t last_tick);
  void publish_status();
  void say_summary();

  Host& host_;
  rt::SchedulerParams sched_;
  graph::FfdNodeConfig config_;
  rt::RtParams rtp_;
  std::unique_ptr<ForceDriver> driver_;
  bool local_hop_;
  bool simulated_;  // the graph's clock: lock-step ticks, every answer waited for
  std::int64_t started_ns_ = 0;  // the wall clock at the loop's start
  std::int64_t end_ns_ = 0;      // the loop's end (duration_s after its start; none: INT64_MAX)
  bool run_over_ = false;        // simulated time: the simulator's answer said the task is completed
  std::unique_ptr<Io> io_;
};

}  // namespace enact::node
