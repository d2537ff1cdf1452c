#include "core/viewer/view_model.h"

#include <cstdio>

#include "core/graph/graph_files.h"
#include "core/graph/messages.h"

namespace enact::viewer {
namespace {

const char* kind_name(msgs::TaskEvent::Kind k) {
  switch (k) {
    case msgs::TaskEvent::TRIAL_START: return "trial start";
    case msgs::TaskEvent::TRIAL_END: return "trial end";
    case msgs::TaskEvent::FALL_START: return "fall";
    case msgs::TaskEvent::FALL_END: return "back on top";
    case msgs::TaskEvent::RESET: return "reset";
    case msgs::TaskEvent::CONDITION: return "condition";
    case msgs::TaskEvent::INTERVAL_START: return "interval start";
    case msgs::TaskEvent::INTERVAL_END: return "interval end";
    case msgs::TaskEvent::ANSWER: return "answer";
    default: return "event";
  }
}

}  // namespace

void ViewModel::on_scene(const msgs::SceneState& m) {
  scene_ = m;
  has_scene_ = true;
  trail_.push(graph::get(m.body_position()));
  force_.push(static_cast<float>(math::norm(graph::get(m.resultant_force()))));
  int touching = 0;
  for (const bool c : m.in_contact()) touching += c;
  contacts_.push(static_cast<float>(touching));
  // the task: where the body is, and the trial's clock (model time)
  task_.on_top = m.on_top();
  task_.progress = m.progress();
  if (restart_pending_) {
    task_.start_ns = m.header().stamp_ns() - resume_ns_;
    restart_pending_ = false;
    resume_ns_ = 0;
  }
  if (task_.running) task_.time_ns = m.header().stamp_ns() - task_.start_ns;
}

void ViewModel::on_shown(const msgs::TactileShown& m) {
  shown_.assign(m.level().begin(), m.level().end());
  shown_rows_ = static_cast<int>(m.rows());
  shown_cols_ = static_cast<int>(m.cols());
}

void ViewModel::on_event(const msgs::TaskEvent& m) {
  switch (m.kind()) {
    case msgs::TaskEvent::FALL_START:
      task_.falls += 1;
      task_.falling = true;
      break;
    case msgs::TaskEvent::FALL_END: task_.falling = false; break;
    case msgs::TaskEvent::TRIAL_END:
      task_.running = false;
      task_.falling = false;
      task_.completed = m.detail().empty();  // the simulator's own end: the bridge was completed
      break;
    case msgs::TaskEvent::TRIAL_START:
      task_ = {};
      restart_pending_ = true;
      break;
    case msgs::TaskEvent::RESET:
      // a reset starts a new trial; a repositioning does not
      if (m.detail() == "reset") {
        task_ = {};
        restart_pending_ = true;
      }
      break;
    default: break;
  }
  note(std::string(kind_name(m.kind())) + (m.detail().empty() ? "" : ": " + m.detail()) + (m.condition().empty() ? "" : " [" + m.condition() + "]"));
}

void ViewModel::on_task_state(const msgs::TaskState& m) {
  task_.falls = m.falls();
  task_.falling = m.falling();
  task_.running = m.phase() == msgs::TaskState::RUNNING;
  task_.completed = m.phase() == msgs::TaskState::COMPLETED;
  task_.time_ns = static_cast<std::int64_t>(m.trial_s() * 1e9);
  // the scene's clock goes on from here
  if (has_scene_) task_.start_ns = scene_.header().stamp_ns() - task_.time_ns;
  restart_pending_ = !has_scene_;
  resume_ns_ = restart_pending_ ? task_.time_ns : 0;
}

void ViewModel::on_status(const msgs::NodeStatus& m, std::int64_t now_ns) { nodes_[m.node()] = {m, now_ns}; }

void ViewModel::on_graph(const msgs::GraphInfo& m, std::int64_t now_ns) {
  graph_ = m.graph();
  last_graph_ns_ = now_ns;
  if (auto named = graph::scene_of(m); named && graph_scene_ != named) graph_scene_ = std::move(named);
}

void ViewModel::on_answer(const graph::ParamAnswer& a) {
  if (a.applied) note(a.name + ": applied");
  else note(a.name + ": refused: " + a.reason);
}

void ViewModel::note(const std::string& line) { log_.push(line); }

void ViewModel::clear() { *this = ViewModel{}; }

LinkState ViewModel::link(std::int64_t now_ns) const {
  if (last_graph_ns_ < 0) return LinkState::waiting;
  return now_ns - last_graph_ns_ > kLost_ns ? LinkState::lost : LinkState::connected;
}

std::string format_ns(std::int64_t ns) {
  char buf[32];
  if (ns >= 10'000'000) std::snprintf(buf, sizeof buf, "%.1f ms", static_cast<double>(ns) * 1e-6);
  else std::snprintf(buf, sizeof buf, "%.2f us", static_cast<double>(ns) * 1e-3);
  return buf;
}

}  // namespace enact::viewer
