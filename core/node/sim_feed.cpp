#include "core/node/sim_feed.h"

namespace enact::node {

SimFeed::SimFeed(const sim::Simulator& simulator, const std::string& name, bus::BytePublisher& out, graph::ParamBoard* board, int rows, int cols,
                 bool simulated)
    : force_pub_(out, graph::kForceCommand),
      frame_pub_(out, graph::kTactileFrame),
      scene_pub_(out, graph::kSceneState),
      event_pub_(out, graph::kTaskEvent),
      keyframe_pub_(out, graph::kSimKeyframe),
      params_(simulator, name, out, event_pub_, board),
      task_state_(out),
      rows_(rows),
      cols_(cols),
      simulated_(simulated) {}

void SimFeed::answer(msgs::ForceCommand& m, const graph::Observation& o, std::uint64_t state_seq, bool simulated) {
  graph::fill(m, state_seq, o.step.force_n, o.step.fault);
  m.set_tactile_frame_seq(o.frame_seq);
  m.set_run_over(simulated && o.step.event.kind == task::TaskEventKind::completed);
  m.mutable_header()->set_seq(o.seq);
  m.mutable_header()->set_stamp_ns(o.force_ns);
}

void SimFeed::intake(graph::ParamQueue& changes) {
  while (const auto change = params_.next()) changes.try_push(*change);
}

void SimFeed::take_applied(graph::AppliedQueue& applied) {
  while (applied.try_pop(done_)) {
    params_.applied(done_);
    task_state_.applied(done_.kind);
  }
}

void SimFeed::step(const graph::Observation& o, std::uint64_t state_seq) {
  params_.stepped(o.seq, state_seq, o.sample.time_ns);
  answer(force_, o, state_seq, simulated_);
  force_pub_.publish(force_, o.seq);
  if (o.frame_seq != 0) {
    // stamped with the sample it came from (in simulated time the tactile driver's clock)
    graph::fill(frame_, rows_, cols_, o.step.frame);
    frame_.mutable_header()->set_stamp_ns(o.sample.time_ns);
    frame_pub_.publish(frame_, o.frame_seq);
    frame_seq_ = o.frame_seq;
  }
  if (graph::fill(event_, o.step.event, params_.model_name_at(o.sample.time_ns))) event_pub_.publish(event_);
  task_state_.step(o.sample.time_ns, o.step);
}

void SimFeed::scene(const Scene& s) {
  graph::fill(scene_, s.snap, params_.model_name_at(s.tick_ns));
  scene_pub_.publish(scene_);
}

void SimFeed::keyframe(const sim::Keyframe& k, const physics::Model& model) {
  graph::fill(keyframe_, k, model);
  keyframe_pub_.publish(keyframe_);
}

void SimFeed::due(std::int64_t now_ns) { task_state_.publish_due(now_ns, params_.model_name()); }

void SimFeed::stopped(std::int64_t time_ns) { say_event(msgs::TaskEvent::TRIAL_END, time_ns, "stopped"); }

void SimFeed::say_event(msgs::TaskEvent::Kind kind, std::int64_t time_ns, const std::string& detail) {
  event_.Clear();
  event_.mutable_header()->set_stamp_ns(time_ns);
  event_.set_kind(kind);
  event_.set_time_ns(time_ns);
  event_.set_detail(detail);
  event_.set_condition(params_.model_name());
  event_pub_.publish(event_);
}

}  // namespace enact::node
