#include "core/node/colocated.h"

#include "core/devices/hand.h"
#include "core/graph/messages.h"

namespace enact::graph {

ColocatedLoop::ColocatedLoop(sim::Simulator& simulator, devices::ForceDevice& force, devices::TactileDevice* tactile, Clock clock,
                             double reengage_s)
    : sim_(simulator), force_(force), clock_(clock), reengage_(reengage_s) {
  if (tactile) tactile_.emplace(*tactile);
}

void ColocatedLoop::activate() {
  force_.activate();
  if (tactile_) tactile_->activate();
  sim_.activate(0);
  for (node::LoopComponent* stage : stages_) stage->activate();
  devices::HandSource* hand = force_.simulated_hand();
  hand_ = hand && hand->feels_pins() && tactile_ ? hand : nullptr;
  start_ns_ = -1;  // the first tick is the simulator's time 0 (as in enact-sim: its first sample)
  obs_ = {};
  reengage_.interrupt();  // the force path starts here
}

void ColocatedLoop::connect_params(ParamQueue& changes, AppliedQueue& applied) {
  changes_ = &changes;
  applied_ = &applied;
}

const Observation& ColocatedLoop::tick(std::int64_t now_ns) {
  if (start_ns_ < 0) start_ns_ = whole_ns_ = now_ns;
  // parameter changes, between the last step and this one
  sim::ParamChange change;
  while (changes_ && changes_->try_pop(change)) applied_->try_push(sim_.apply(change, now_ns));
  // read the device, step the model on that sample, write the force, in one tick
  force_.read(now_ns, obs_.sample);
  obs_.cut = force_path_cut(device_faults(obs_.sample.faults));
  if (obs_.cut) reengage_.interrupt();
  else whole_ns_ = now_ns;
  obs_.cut_since_ns = obs_.cut ? whole_ns_ : 0;
  const std::int64_t t_ns = now_ns - start_ns_;
  obs_.step = sim_.step(t_ns, reengage_.position(sim_, t_ns, obs_.sample.position_m));
  node::Tick stage_tick{now_ns, t_ns, &obs_.sample, &obs_.step};
  for (node::LoopComponent* stage : stages_) stage->step(stage_tick);
  force_.write(now_ns, obs_.step.force_n);
  obs_.force_ns = clock_ ? clock_() : now_ns;
  // pins only at the down-sampled rate the cells can follow
  if (tactile_ && obs_.step.frame_due) tactile_->apply(now_ns, obs_.step.frame, ++frames_);
  // a virtual subject's fingertip feels what the pins show
  if (hand_) {
    tactile_->levels(now_ns, felt_);
    hand_->feel_pins(felt_, tactile_->rows(), tactile_->cols());
  }
  if (obs_.step.event.kind != task::TaskEventKind::none) obs_.step.event.time_ns += start_ns_;  // on the monotonic clock
  obs_.seq += 1;
  return obs_;
}

void ColocatedLoop::deactivate() noexcept {
  force_.deactivate();
  if (tactile_) tactile_->deactivate();
  sim_.deactivate();
  for (node::LoopComponent* stage : stages_) stage->deactivate();
}

}  // namespace enact::graph
