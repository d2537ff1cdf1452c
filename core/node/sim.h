#pragma once
// The simulator of a distributed graph (enact-sim). It steps once per DeviceState and
// answers at once with the ForceCommand carrying the sequence number it answers, over the
// FFD driver's same-host link when it has one, the bus otherwise; it also publishes the
// down-sampled tactile frames, the scene (decimated), task events and status. Live
// parameter changes are planned on the ParamPort's thread and applied between two steps.
#include <cstdint>
#include <memory>
#include <string>

#include "core/node/host.h"
#include "core/params/device_config.h"
#include "core/sim/simulator.h"
#include "msgs/device_state.pb.h"

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
  struct Io;  // sockets, publishers, parameter port: made by open_ports()
  bool next_state(std::int64_t timeout_ns);
  void answer(std::int64_t received_ns);
  void publish_outputs(const sim::StepOutput& o, std::int64_t received_ns);
  void apply_params();
  void restart_begins();
  std::string summary() const;

  Host& host_;
  sim::Simulator simulator_;
  graph::SimNodeConfig config_;
  bool local_hop_;
  bool simulated_;  // the graph's clock: the frames carry the sample's time
  std::unique_ptr<Io> io_;
  msgs::DeviceState state_;
  std::int64_t next_scene_ = 0, next_status_ = 0, next_params_ = 0, next_link_try_ns_ = 0, next_keyframe_ = 0;
  std::int64_t scene_period_ns_ = 0, restart_ns_ = 0;
  std::uint64_t steps_ = 0;
  int respawn_ = 0;
  bool restart_event_due_ = false;
};

}  // namespace enact::node
