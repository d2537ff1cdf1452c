#include "core/graph/task_state.h"

#include <algorithm>

#include "core/graph/topics.h"

namespace enact::graph {
namespace {

// the period of task/state when nothing changes
constexpr std::int64_t kPeriod_ns = 100'000'000;

}  // namespace

TaskStateTracker::TaskStateTracker(bus::BytePublisher& out) : pub_(out, kTaskState) {
  msg_.set_trial(0);
  begin_trial();
}

void TaskStateTracker::begin_trial() {
  msg_.set_phase(msgs::TaskState::RUNNING);
  msg_.set_trial(msg_.trial() + 1);
  msg_.set_falls(0);
  msg_.set_trial_s(0.0);
  msg_.set_time_out_s(0.0);
  msg_.set_progress(0.0);
  start_ns_ = -1;
  fall_since_ns_ = -1;
  closed_out_ns_ = 0;
  changed_ = true;
}

void TaskStateTracker::step(std::int64_t time_ns, const sim::StepOutput& o) {
  if (msg_.phase() != msgs::TaskState::RUNNING) return;
  if (start_ns_ < 0) start_ns_ = time_ns;
  last_ns_ = time_ns;
  if (o.on_top) msg_.set_progress(std::max(msg_.progress(), o.progress));
  switch (o.event.kind) {
    case task::TaskEventKind::fall_start:
      msg_.set_falls(msg_.falls() + 1);
      fall_since_ns_ = o.event.time_ns;
      changed_ = true;
      break;
    case task::TaskEventKind::fall_end:
      if (fall_since_ns_ >= 0) closed_out_ns_ += o.event.time_ns - fall_since_ns_;
      fall_since_ns_ = -1;
      changed_ = true;
      break;
    case task::TaskEventKind::completed:
      if (fall_since_ns_ >= 0) closed_out_ns_ += o.event.time_ns - fall_since_ns_;
      fall_since_ns_ = -1;
      last_ns_ = o.event.time_ns;
      msg_.set_phase(msgs::TaskState::COMPLETED);
      changed_ = true;
      break;
    case task::TaskEventKind::none: break;
  }
  msg_.set_falling(fall_since_ns_ >= 0);
  const std::int64_t open_ns = fall_since_ns_ >= 0 ? std::max<std::int64_t>(0, last_ns_ - fall_since_ns_) : 0;
  msg_.set_time_out_s(static_cast<double>(closed_out_ns_ + open_ns) * 1e-9);
  msg_.set_trial_s(static_cast<double>(std::max<std::int64_t>(0, last_ns_ - start_ns_)) * 1e-9);
}

void TaskStateTracker::applied(sim::ParamKind kind) {
  if (kind == sim::ParamKind::reset || kind == sim::ParamKind::trial_start) begin_trial();
  if (kind == sim::ParamKind::trial_stop && msg_.phase() == msgs::TaskState::RUNNING) {
    msg_.set_phase(msgs::TaskState::STOPPED);
    changed_ = true;
  }
  if (kind == sim::ParamKind::model) changed_ = true;
}

void TaskStateTracker::publish_due(std::int64_t now_ns, const std::string& model) {
  if (model != msg_.model()) {
    msg_.set_model(model);
    changed_ = true;
  }
  if (!changed_ && now_ns < next_ns_) return;
  msg_.mutable_header()->set_stamp_ns(0);
  pub_.publish(msg_);
  changed_ = false;
  next_ns_ = now_ns + kPeriod_ns;
}

}  // namespace enact::graph
