#pragma once
// The co-located real-time container (enact-rt). The simulator and both device drivers run
// in one process and one real-time thread (read device, step, write force, write pins, in
// the same tick: graph::ColocatedLoop, with the stages a user's plugin libraries give
// between the model and the force); observers are fed from lock-free queues by a
// non-real-time thread, which also plans live parameter changes and hands them to the loop.
#include <atomic>
#include <cstdint>
#include <deque>
#include <vector>
#include <memory>
#include <string>
#include <thread>

#include "core/devices/device.h"
#include "core/node/colocated.h"
#include "core/node/force_driver.h"
#include "core/params/device_config.h"
#include "core/params/params.h"
#include "core/node/host.h"
#include "core/node/loop_component.h"
#include "core/node/recorder.h"
#include "core/rt/rt_setup.h"
#include "core/rt/scheduler.h"
#include "core/sim/simulator.h"

namespace enact::node {

extern const NodeKind kContainer;

class Container {
 public:
  explicit Container(Host& host);  // components configured: bad input refused here
  ~Container();
  // its lifecycle in the process host (host_main)
  void open_ports();
  void activate();
  void run();
  int deactivate();

 private:
  struct Io;  // publishers, queues, the loop: made by open_ports()
  void rt_main();
  std::size_t drain();
  void publish_tick();
  void take_applied();
  void publish_status();
  void print_summary();
  void publish_limit();
  void plan_wait(double spin_us);
  template <typename Queue, typename Item>
  bool deliver(Queue& queue, const Item& item);

  Host& host_;
  std::string sim_name_, ffd_name_, tac_name_;
  graph::Params sim_p_, ffd_p_, tac_p_;
  // the components beside sim, ffd and tactile: observers and stages, each with its parameters
  // (an observer holds a reference to them)
  struct Member {
    std::string name, plugin;
    graph::Params params;
  };
  std::deque<Member> members_;
  rt::SchedulerParams sched_;
  rt::RtParams rtp_;
  std::string wait_why_;
  double spin_floor_ = -1.0;  // spinning whole: what a thread spinning with no work misses here (the probe's)
  rt::GraphClock clock_ = rt::GraphClock::real;
  graph::RtConfig config_;  // its own parameters
  ObserverGroup observers_;  // observer components, beside the loop
  std::vector<std::unique_ptr<LoopComponent>> stages_;  // stages of the tick, in order
  sim::Simulator simulator_;
  std::unique_ptr<ForceDriver> force_;
  std::unique_ptr<devices::TactileDevice> tactile_;
  std::unique_ptr<Io> io_;
  std::thread rt_thread_;  // the loop's, from activate() to deactivate()
  std::atomic<bool> rt_done_{false};
  std::int64_t run_ns_ = 0;  // the loop's wall-clock time (read after rt_done_)
  std::atomic<std::int64_t> limit_ns_{-1};  // the last tick's time, when duration_s ended the loop
};

}  // namespace enact::node
