#include "core/node/sim_step.h"

namespace enact::node {

void SimStep::activate() {
  sim_.activate(0);
  for (LoopComponent* stage : stages_) stage->activate();
  steps_ = frames_ = 0;
}

void SimStep::step(std::int64_t time_ns, graph::Observation& o) noexcept {
  // parameter changes, between the last step and this one
  sim::ParamChange change;
  while (changes_ && changes_->try_pop(change)) applied_->try_push(sim_.apply(change, time_ns));
  o.step = sim_.step_sample(time_ns, o.sample.position_m, o.cut);
  Tick tick{time_ns, time_ns - sim_.origin_ns(), &o.sample, &o.step};
  for (LoopComponent* stage : stages_) stage->step(tick);
  o.seq = ++steps_;
  o.frame_seq = o.step.frame_due ? ++frames_ : 0;
}

void SimStep::deactivate() noexcept {
  sim_.deactivate();
  for (LoopComponent* stage : stages_) stage->deactivate();
}

}  // namespace enact::node
