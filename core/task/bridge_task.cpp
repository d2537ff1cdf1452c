#include "core/task/bridge_task.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace enact::task {
namespace {

std::int64_t duration_ns(double seconds, const char* name) {
  if (!std::isfinite(seconds) || seconds < 0.0) {
    throw std::invalid_argument(std::string("TaskParams.") + name + " must be a finite duration >= 0 s, got " +
                                std::to_string(seconds));
  }
  return std::llround(seconds * 1e9);
}

double seconds(std::int64_t ns) { return static_cast<double>(ns) * 1e-9; }

}  // namespace

BridgeTask::BridgeTask(TaskParams params)
    : min_fall_ns_(duration_ns(params.min_fall_s, "min_fall_s")),
      min_recovery_ns_(duration_ns(params.min_recovery_s, "min_recovery_s")),
      end_progress_(params.end_progress) {
  if (!(end_progress_ > 0.0 && end_progress_ <= 1.0)) {
    throw std::invalid_argument("TaskParams.end_progress must lie in (0, 1], got " + std::to_string(end_progress_));
  }
  reset(0);
}

void BridgeTask::reset(std::int64_t start_ns) {
  phase_ = Phase::on_top;
  start_ns_ = start_ns;
  last_ns_ = start_ns;
  lost_ns_ = start_ns;
  regained_ns_ = start_ns;
  closed_out_ns_ = 0;
  completed_ns_ = start_ns;
  falls_ = 0;
  completed_ = false;
  progress_ = 0.0;
}

TaskEvent BridgeTask::update(std::int64_t time_ns, bool on_top, double progress) {
  if (completed_ || time_ns < last_ns_) return {};
  last_ns_ = time_ns;

  // furthest progress on top (a NaN fails both comparisons and is ignored)
  if (on_top && progress > progress_) progress_ = progress < 1.0 ? progress : 1.0;

  const TaskEvent event = advance(time_ns, on_top);

  // completion closes a fall still open at this time
  if (on_top && progress >= end_progress_) {
    if (falling()) closed_out_ns_ += time_ns - lost_ns_;
    phase_ = Phase::on_top;
    completed_ = true;
    completed_ns_ = time_ns;
    return {TaskEventKind::completed, time_ns};
  }
  return event;
}

TaskEvent BridgeTask::advance(std::int64_t time_ns, bool on_top) {
  switch (phase_) {
    case Phase::on_top:
      if (on_top) return {};
      phase_ = Phase::pending_off;
      lost_ns_ = time_ns;
      [[fallthrough]];  // with min_fall_s = 0 the loss is a fall at once

    case Phase::pending_off:
      // off for min_fall_s (up to this sample): a fall, which began when contact was lost
      if (time_ns - lost_ns_ >= min_fall_ns_) {
        ++falls_;
        phase_ = on_top ? Phase::pending_on : Phase::falling;
        regained_ns_ = time_ns;
        return {TaskEventKind::fall_start, lost_ns_};
      }
      if (on_top) phase_ = Phase::on_top;
      return {};

    case Phase::falling:
      if (!on_top) return {};
      phase_ = Phase::pending_on;
      regained_ns_ = time_ns;
      [[fallthrough]];  // with min_recovery_s = 0 the fall ends at once

    case Phase::pending_on:
      // on for min_recovery_s (up to this sample): the fall ended when contact was regained
      if (time_ns - regained_ns_ >= min_recovery_ns_) {
        closed_out_ns_ += regained_ns_ - lost_ns_;
        phase_ = on_top ? Phase::on_top : Phase::pending_off;
        lost_ns_ = time_ns;
        return {TaskEventKind::fall_end, regained_ns_};
      }
      if (!on_top) phase_ = Phase::falling;
      return {};
  }
  return {};
}

Metrics BridgeTask::metrics() const {
  Metrics m;
  m.falls = falls_;
  m.completed = completed_;
  m.progress = progress_;
  const std::int64_t end_ns = completed_ ? completed_ns_ : last_ns_;
  // a fall still open counts up to the last sample; a pending loss is not a fall yet
  const std::int64_t open_out_ns = falling() ? last_ns_ - lost_ns_ : 0;
  m.time_total_s = seconds(end_ns - start_ns_);
  m.time_out_s = seconds(closed_out_ns_ + open_out_ns);
  m.ratio = m.time_total_s > 0.0 ? m.time_out_s / m.time_total_s : 0.0;
  return m;
}

BridgeTask::Account BridgeTask::account() const {
  return {start_ns_, falls_, closed_out_ns_, falling() ? lost_ns_ : -1, completed_ ? completed_ns_ : -1, last_ns_};
}

bool BridgeTask::falling() const { return phase_ == Phase::falling || phase_ == Phase::pending_on; }

}  // namespace enact::task
