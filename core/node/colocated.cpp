#include "core/node/colocated.h"

#include "core/devices/hand.h"
#include "core/graph/messages.h"

namespace enact::graph {

ColocatedLoop::ColocatedLoop(sim::Simulator& simulator, devices::ForceDevice& force, devices::TactileDevice* tactile, Clock clock)
    : sim_(simulator), force_(force), clock_(clock) {
  if (tactile) tactile_.emplace(*tactile);
}

void ColocatedLoop::activate() {
  force_.activate();
  if (tactile_) tactile_->activate();
  sim_.activate(0);  // its first sample, the first tick's, is its time 0; the force path starts here
  for (node::LoopComponent* stage : stages_) stage->activate();
  devices::HandSource* hand = force_.simulated_hand();
  hand_ = hand && hand->feels_pins() && tactile_ ? hand : nullptr;
  obs_ = {};
}

void ColocatedLoop::connect_params(ParamQueue& changes, AppliedQueue& applied) {
  changes_ = &changes;
  applied_ = &applied;
}

const Observation& ColocatedLoop::tick(std::int64_t now_ns) {
  if (sim_.origin_ns() < 0) whole_ns_ = now_ns;
  // parameter changes, between the last step and this one
  sim::ParamChange change;
  while (changes_ && changes_->try_pop(change)) applied_->try_push(sim_.apply(change, now_ns));
  // read the device, step the model on that sample, write the force, in one tick
  force_.read(now_ns, obs_.sample);
  obs_.cut = force_path_cut(device_faults(obs_.sample.faults));
  if (!obs_.cut) whole_ns_ = now_ns;
  obs_.cut_since_ns = obs_.cut ? whole_ns_ : 0;
  obs_.step = sim_.step_sample(now_ns, obs_.sample.position_m, obs_.cut);
  node::Tick stage_tick{now_ns, now_ns - sim_.origin_ns(), &obs_.sample, &obs_.step};
  for (node::LoopComponent* stage : stages_) stage->step(stage_tick);
  force_.write(now_ns, obs_.step.force_n);
  obs_.force_ns = clock_ ? clock_() : now_ns;
  // pins only at the down-sampled rate the cells can follow
  obs_.frame_seq = obs_.step.frame_due ? ++frames_ : 0;
  if (tactile_ && obs_.step.frame_due) tactile_->apply(now_ns, obs_.step.frame, frames_);
  // a virtual subject's fingertip feels what the pins show
  if (hand_) {
    tactile_->levels(now_ns, felt_);
    hand_->feel_pins(felt_, tactile_->rows(), tactile_->cols());
  }
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
