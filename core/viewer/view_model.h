#pragma once
// What the viewer knows of a graph, fed with the messages it receives: the latest scene, a
// trail of the body and scrolling histories of force and contacts, the pins as shown, the
// task state, every node's status, and a log of events and parameter answers. No drawing
// here (draw.h), no sockets (link.h).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/params/param_bus.h"
#include "core/math/vec3.h"
#include "core/viewer/ring.h"
#include "core/viewer/scene_geometry.h"
#include "msgs/graph.pb.h"
#include "msgs/task_state.pb.h"
#include "msgs/node_status.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"

namespace enact::viewer {

enum class LinkState : std::uint8_t {
  waiting,    // no graph has answered yet
  connected,  // GraphInfo arrives (every second)
  lost,       // it stopped arriving: the graph ended, or the network went away
};

// one node's last NodeStatus and when it came
struct NodeRow {
  msgs::NodeStatus status;
  std::int64_t received_ns = 0;
};

// the bridge task as seen from task/state, its events and the scene
struct TaskView {
  bool on_top = false;
  double progress = 0.0;
  int falls = 0;
  bool falling = false;
  bool running = true;       // a trial is running (stopped by TRIAL_END)
  bool completed = false;    // the end of the bridge was reached
  std::int64_t start_ns = 0; // model time the trial started
  std::int64_t time_ns = 0;  // model time into the trial (frozen when it ends)
};

class ViewModel {
 public:
  static constexpr std::size_t kHistory = 600;  // scene samples kept (10 s at 60 Hz)
  static constexpr double kSceneRate_hz = 60.0;  // sim/scene as the graph sends it to observers
  static constexpr std::size_t kLog = 8;        // log lines kept
  static constexpr std::int64_t kLost_ns = 3'000'000'000;  // no GraphInfo for this long: lost

  void on_scene(const msgs::SceneState& m);
  void on_shown(const msgs::TactileShown& m);
  void on_event(const msgs::TaskEvent& m);
  // the trial as the simulator counts it (latched: what a late viewer sees first)
  void on_task_state(const msgs::TaskState& m);
  void on_status(const msgs::NodeStatus& m, std::int64_t now_ns);
  void on_graph(const msgs::GraphInfo& m, std::int64_t now_ns);
  void on_answer(const graph::ParamAnswer& a);
  // a line of the log (the viewer's own notes)
  void note(const std::string& line);
  // forget the graph: a new one is being attached
  void clear();

  LinkState link(std::int64_t now_ns) const;
  const std::string& graph_name() const { return graph_; }
  // the scene the graph's simulator runs, when its GraphInfo carries it (graphs started by
  // `enact launch`)
  const std::optional<NamedScene>& graph_scene() const { return graph_scene_; }

  bool has_scene() const { return has_scene_; }
  const msgs::SceneState& scene() const { return scene_; }
  // the body centre over the last kHistory scenes, m
  const Ring<math::Vec3, kHistory>& trail() const { return trail_; }
  // |resultant force| (N) and grid masses in contact, per scene
  const Ring<float, kHistory>& force_history() const { return force_; }
  const Ring<float, kHistory>& contact_history() const { return contacts_; }
  // pins as the tactile device shows them, row-major, [0, 1] (empty before tactile/shown)
  const std::vector<float>& shown() const { return shown_; }
  int shown_rows() const { return shown_rows_; }
  int shown_cols() const { return shown_cols_; }
  const TaskView& task() const { return task_; }
  const std::map<std::string, NodeRow>& nodes() const { return nodes_; }
  const Ring<std::string, kLog>& log() const { return log_; }

 private:
  std::string graph_;
  std::int64_t last_graph_ns_ = -1;
  std::optional<NamedScene> graph_scene_;
  bool has_scene_ = false;
  msgs::SceneState scene_;
  Ring<math::Vec3, kHistory> trail_;
  Ring<float, kHistory> force_;
  Ring<float, kHistory> contacts_;
  std::vector<float> shown_;
  int shown_rows_ = 0, shown_cols_ = 0;
  TaskView task_;
  bool restart_pending_ = false;  // a trial (re)started: its model time starts at the next scene
  std::int64_t resume_ns_ = 0;    // the trial time the next scene continues from (task/state before any scene)
  std::map<std::string, NodeRow> nodes_;
  Ring<std::string, kLog> log_;
};

// "12.3 us" style: ns shown in us with 2 decimals, or ms past 10 ms
std::string format_ns(std::int64_t ns);

}  // namespace enact::viewer
