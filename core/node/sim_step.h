#pragma once
// The simulator's step, one for both hosts: the parameter changes planned since the last
// step swapped in, the model stepped on the device's sample, a user's stages
// (node/loop_component.h) after it in their order, the step and its tactile frame numbered.
// The co-located tick (node/colocated.h) calls it between reading the device and writing the
// force; enact-sim (node/sim.h) between receiving a DeviceState and answering it. On the loop:
// allocates nothing, locks nothing, never blocks and never throws.
#include <cstdint>
#include <vector>

#include "core/devices/device.h"
#include "core/node/loop_component.h"
#include "core/rt/spsc_queue.h"
#include "core/sim/params.h"
#include "core/sim/simulator.h"

namespace enact::graph {

// one step, for observers (through an SPSC queue to the thread that publishes)
struct Observation {
  std::uint64_t seq = 0;        // step number, from 1
  std::int64_t force_ns = 0;    // force written, or answered (latency from the step's time = force_ns - sample.time_ns)
  devices::ForceSample sample;  // what the device read (position, velocity, buttons, fault bits)
  sim::StepOutput step;         // what the model made of it: force, pins, frame, contacts, task
  // whether the force path is cut (the device's watchdog tripped, i.e. this tick came later
  // than its watchdog time after the last, or the device could not be read), and since when:
  // the time of the last tick before the cut that read the device well (the co-located tick's)
  bool cut = false;
  std::int64_t cut_since_ns = 0;
  std::uint64_t frame_seq = 0;  // the step's tactile frame, numbered from 1 (0: none due)
};

// parameter changes into the loop, and what it applied back out (a ParamPort never has
// more than sim::kMaxParamsInFlight in flight, so neither queue overflows)
using ParamQueue = rt::SpscQueue<sim::ParamChange, sim::kMaxParamsInFlight>;
using AppliedQueue = rt::SpscQueue<sim::ParamApplied, sim::kMaxParamsInFlight>;

}  // namespace enact::graph

namespace enact::node {

class SimStep {
 public:
  explicit SimStep(sim::Simulator& simulator) : sim_(simulator) {}

  // a stage after those added before (it outlives this); before activate()
  void add_stage(LoopComponent& stage) { stages_.push_back(&stage); }
  // from now on, take the changes waiting in `changes` before each step, apply them and
  // report them in `applied` (both outlive this; the loop's thread pops one, pushes the other)
  void connect_params(graph::ParamQueue& changes, graph::AppliedQueue& applied) {
    changes_ = &changes;
    applied_ = &applied;
  }
  // the simulator from its time 0 (its first step's), then the stages, on the calling thread
  void activate();
  // one step at time_ns (the graph clock's: the tick's deadline, the sample's stamp) on
  // o.sample, cut or not (o.cut: the body re-synchronised with the device first, so the force
  // comes back from zero): fills o.step, o.seq and o.frame_seq
  void step(std::int64_t time_ns, graph::Observation& o) noexcept;
  // the simulator stopped, then the stages
  void deactivate() noexcept;

  std::uint64_t steps() const { return steps_; }

 private:
  sim::Simulator& sim_;
  graph::ParamQueue* changes_ = nullptr;
  graph::AppliedQueue* applied_ = nullptr;
  std::vector<LoopComponent*> stages_;
  std::uint64_t steps_ = 0, frames_ = 0;
};

}  // namespace enact::node
