#include "core/node/colocated.h"

#include "core/devices/hand.h"
#include "core/graph/messages.h"

namespace enact::graph {

ColocatedLoop::ColocatedLoop(sim::Simulator& simulator, devices::ForceDevice& force, devices::TactileDevice* tactile, Clock clock)
    : sim_(simulator), force_(force), clock_(clock), step_(simulator) {
  if (tactile) tactile_.emplace(*tactile);
}

void ColocatedLoop::activate() {
  force_.activate();
  if (tactile_) tactile_->activate();
  step_.activate();  // the simulator's first sample, the first tick's, is its time 0; the force path starts here
  devices::HandSource* hand = force_.simulated_hand();
  hand_ = hand && hand->feels_pins() && tactile_ ? hand : nullptr;
  obs_ = {};
}

const Observation& ColocatedLoop::tick(std::int64_t now_ns) {
  if (sim_.origin_ns() < 0) whole_ns_ = now_ns;
  // read the device, step the model on that sample (the parameter changes planned since the
  // last step swapped in first, the stages after it), write the force, in one tick
  force_.read(now_ns, obs_.sample);
  obs_.cut = force_path_cut(device_faults(obs_.sample.faults));
  if (!obs_.cut) whole_ns_ = now_ns;
  obs_.cut_since_ns = obs_.cut ? whole_ns_ : 0;
  step_.step(now_ns, obs_);
  force_.write(now_ns, obs_.step.force_n);
  obs_.force_ns = clock_ ? clock_() : now_ns;
  // pins only at the down-sampled rate the cells can follow
  if (tactile_ && obs_.step.frame_due) tactile_->apply(now_ns, obs_.step.frame, obs_.frame_seq);
  // a virtual subject's fingertip feels what the pins show
  if (hand_) {
    tactile_->levels(now_ns, felt_);
    hand_->feel_pins(felt_, tactile_->rows(), tactile_->cols());
  }
  return obs_;
}

void ColocatedLoop::deactivate() noexcept {
  force_.deactivate();
  if (tactile_) tactile_->deactivate();
  step_.deactivate();
}

}  // namespace enact::graph
