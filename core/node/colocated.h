#pragma once
// The co-located real-time tick: the simulator and both device drivers in one thread, wired
// by calls: read the device, step the model, the stages (node/loop_component.h: a user's, in
// their order), write the force, write the pins (down-sampled), all in the same tick: the
// zero-delay loop. A simulated hand that feels pins (a virtual
// subject) is given what the tactile device shows at the end of each tick. The tactile
// device is optional: without one the model's frames are observed, written nowhere. What happened is
// returned as a trivially copyable record for the observers' queue. tick() allocates nothing, locks nothing, never
// blocks and never throws.
#include <cstdint>
#include <optional>
#include <vector>

#include "core/devices/device.h"
#include "core/node/sim_step.h"
#include "core/node/tactile_driver.h"
#include "core/rt/clock.h"
#include "core/sim/simulator.h"

namespace enact::graph {

// reads the monotonic clock (ns) when the force is written (the tick's latency); a parameter
// so tests can drive time; nullptr in simulated time: the force is written at the tick's time
using Clock = rt::ClockFn;

class ColocatedLoop {
 public:
  // tactile: nullptr for none (a simulated hand that feels pins then feels nothing: the
  // container refuses that graph)
  ColocatedLoop(sim::Simulator& simulator, devices::ForceDevice& force, devices::TactileDevice* tactile, Clock clock);

  // a stage of the tick, after those added before (it outlives the loop); before activate()
  void add_stage(node::LoopComponent& stage) { step_.add_stage(stage); }
  // activate the devices, the simulator and the stages; zero force, pins down. The first tick is the
  // simulator's time 0 (as a distributed simulator's first sample), so a recording of the
  // device states replays exactly (enact resim)
  void activate();
  // from now on, take the changes waiting in `changes` at the top of each tick, apply them
  // and report them in `applied` (both outlive the loop; this thread pops `changes` and
  // pushes `applied`)
  void connect_params(ParamQueue& changes, AppliedQueue& applied) { step_.connect_params(changes, applied); }
  // one tick of the zero-delay loop at now_ns, the tick's time on the graph clock (its
  // deadline: the model, the devices and a virtual subject take their time from it alone): parameter changes first, between two steps; after a cut
  // of the force path (the sample's watchdog or device error bit) the body is re-synchronised
  // with the device first, as enact-sim does, so the force comes back from zero
  const Observation& tick(std::int64_t now_ns);
  // zero the force and lower the pins first, then stop the simulator and the stages
  void deactivate() noexcept;
  // the tactile display's driver (nullptr: none): what its pins show, its summary
  const node::TactileDriver* tactile() const { return tactile_ ? &*tactile_ : nullptr; }

 private:
  sim::Simulator& sim_;
  devices::ForceDevice& force_;
  std::optional<node::TactileDriver> tactile_;  // none: no tactile display
  Clock clock_;
  node::SimStep step_;  // the simulator's step, the stages after it
  devices::HandSource* hand_ = nullptr;  // a simulated hand that feels the pins, if any
  float felt_[32] = {};  // what the virtual subject's fingertip feels
  Observation obs_;
  std::int64_t whole_ns_ = 0;   // the last tick whose sample said the force path was whole
};

}  // namespace enact::graph
