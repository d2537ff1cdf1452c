#pragma once
// The simulator of a distributed graph (enact-sim). Its loop thread steps once per
// DeviceState and answers at once with the ForceCommand carrying the sequence number it
// answers, over the FFD driver's same-host link when it has one; between two steps it swaps
// in the parameter changes planned beside it. Everything else is done on the process's other
// thread by the simulator's feed, as in the co-located container (node/sim_feed.h): the
// answers on the bus (the answer itself on the bus hop, woken at once), the down-sampled
// tactile frames, the scene (decimated), keyframes, task events and state, parameter requests
// and acks, status. Stages a user writes (node/loop_component.h, --component and --library as
// for enact-rt) step after the model and before the answer, in their order, as in the
// co-located tick.
#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <thread>

#include "core/node/host.h"
#include "core/node/loop_component.h"
#include "core/node/sim_step.h"
#include "core/params/device_config.h"
#include "core/sim/simulator.h"

namespace enact::node {

extern const NodeKind kSim;

class Sim {
 public:
  explicit Sim(Host& host);  // the simulator configured from its parameters
  ~Sim();
  // its lifecycle in the process host (host_main)
  void open_ports();
  void activate();
  void run();
  int deactivate();

 private:
  struct Io;  // sockets, queues, the feed: made by open_ports()
  void loop_main();
  bool next_state(std::int64_t deadline_ns);
  void answer(std::int64_t received_ns);
  void hand_over(std::int64_t received_ns);
  std::size_t drain();
  void restart_begins();
  std::string summary() const;
  void make_stages();

  Host& host_;
  sim::Simulator simulator_;
  SimStep step_{simulator_};  // the loop's: the model's step and the stages after it
  graph::SimNodeConfig config_;
  bool local_hop_;
  bool simulated_;  // the graph's clock: the frames carry the sample's time
  // a user's stages, in their order (each with its parameters: COMPONENT.PARAM)
  struct Stage {
    std::string name, plugin;
    graph::Params params;
    std::unique_ptr<LoopComponent> stage;
  };
  std::deque<Stage> stages_;
  std::unique_ptr<Io> io_;
  std::thread loop_;  // the answering thread, from run() to deactivate()
  std::atomic<bool> loop_active_{false}, loop_done_{false};
  // the loop thread's
  std::int64_t next_scene_ = 0, next_status_ = 0, next_link_try_ns_ = 0, next_keyframe_ = 0;
  std::int64_t scene_period_ns_ = 0;
  // the feed's: a restarted simulator's trial start, said once the loop runs
  std::int64_t restart_ns_ = 0;
  int respawn_ = 0;
};

}  // namespace enact::node
