#include "core/graph/colocated.h"

namespace enact::graph {

ColocatedLoop::ColocatedLoop(sim::Simulator& simulator, devices::ForceDevice& force, devices::TactileDevice& tactile, Clock clock)
    : sim_(simulator), force_(force), tactile_(tactile), clock_(clock) {}

void ColocatedLoop::activate(std::int64_t now_ns) {
  force_.activate();
  tactile_.activate();
  sim_.activate(0);
  start_ns_ = now_ns;
  obs_ = {};
}

const Observation& ColocatedLoop::tick(std::int64_t now_ns) {
  // read the device, step the model on that sample, write the force, in one tick
  force_.read(now_ns, sample_);
  const sim::StepOutput& out = sim_.step(now_ns - start_ns_, sample_.position_m);
  force_.write(now_ns, out.force_n);
  const std::int64_t force_ns = clock_();
  // pins only at the down-sampled rate the cells can follow
  if (out.frame_due) tactile_.write(now_ns, out.frame);
  obs_.seq += 1;
  obs_.sample_ns = now_ns;
  obs_.force_ns = force_ns;
  obs_.position_m = sample_.position_m;
  obs_.velocity_m_per_s = sample_.velocity_m_per_s;
  obs_.force_n = out.force_n;
  obs_.buttons = sample_.buttons;
  obs_.device_faults = sample_.faults;
  obs_.pins = out.pins;
  obs_.frame = out.frame;
  obs_.frame_due = out.frame_due;
  obs_.sim_fault = out.fault;
  obs_.contacts = out.contacts;
  obs_.on_top = out.on_top;
  obs_.progress = out.progress;
  obs_.event = out.event;
  if (obs_.event.kind != task::TaskEventKind::none) obs_.event.time_ns += start_ns_;  // on the monotonic clock
  return obs_;
}

void ColocatedLoop::deactivate() noexcept {
  force_.deactivate();
  tactile_.deactivate();
  sim_.deactivate();
}

}  // namespace enact::graph
