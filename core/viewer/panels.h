#pragma once
// The viewer's ImGui windows, each at its place of the layout: the task state, every node's
// status, the scrolling plot of force and contacts, and the experimenter's controls (their
// requests checked against the stability analysis before they are sent).
#include <cstdint>
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/params/param_bus.h"
#include "core/sim/params.h"
#include "core/viewer/layout.h"
#include "core/viewer/view_model.h"
#include "msgs/param_update.pb.h"

namespace enact::viewer {

// the link's line: waiting for `where` (what the viewer follows), or the graph's name and
// `where` (its endpoint) once attached, or lost
std::string link_line(LinkState state, const std::string& graph_name, const std::string& where);
// where the body is for the task: on or off its surface (the scene's task surface, named), or
// that the scene has no task (`surface` empty)
std::string place_line(const TaskView& task, const std::string& surface);
// the link (or, given `recording`, that one), the task (on or off its surface, falls, time,
// progress; a scene without a task says so, and counts nothing)
void task_window(const Rect& r, const ViewModel& model, std::int64_t now_ns, const std::string& source, const std::string& surface,
                 const std::string& recording = "");
// one row per node: rate, loop latency percentiles, overruns, drops, faults, age
void status_window(const Rect& r, const ViewModel& model, std::int64_t now_ns);
// |F| and the contact count over the last ViewModel::kHistory scenes
void plot_window(const Rect& r, const ViewModel& model);

// keyboard shortcuts of the controls (docs/viewer.md, "Keys")
enum class KeyAction : std::uint8_t { cm0, cm1, cm2, cm3, reset, reposition, trial_toggle, stiffer, softer, threshold_up, threshold_down };
std::optional<KeyAction> key_action(char key);

class Controls {
 public:
  // `sim` names the simulator in parameter names ("sim" -> "sim.model"); the pre-check
  // loads `scene_file` (when it cannot, requests go unchecked and the simulator decides)
  Controls(std::string sim, std::string scene_file);

  // the pre-check at this loop rate (the simulator's NodeStatus.rate_hz); rebuilt on change
  void set_rate(double rate_hz);

  // the controls window; the requests made with it this frame
  std::vector<msgs::ParamUpdate> draw(const Rect& r, const ViewModel& model);
  // the requests a key makes
  std::vector<msgs::ParamUpdate> on_key(KeyAction action, const ViewModel& model);

  // a request went out with this id; its answer came (applied ones update the pre-check)
  void sent(std::uint64_t id, const msgs::ParamUpdate& update);
  void answered(const graph::ParamAnswer& answer);

  // the last pre-check refusal or answer, for people
  const std::string& status() const { return status_; }
  // the pre-check's view of the body contacts (0 without a pre-check)
  double stiffness_n_per_m() const;
  double damping_n_s_per_m() const;
  double threshold_m() const;

  // a request for `param` (without the simulator's name); nullopt, with status() saying
  // why, when the pre-check refuses it
  std::optional<msgs::ParamUpdate> request(const std::string& param, const sim::ParamValue& value);

 private:
  void rebuild();

  std::string sim_;
  std::string scene_;
  double rate_hz_ = 0.0;
  std::unique_ptr<sim::ParamPlanner> planner_;
  std::vector<std::pair<std::string, sim::ParamValue>> applied_;  // replayed on a rebuild
  std::map<std::uint64_t, std::pair<std::string, sim::ParamValue>> in_flight_;
  std::string status_;
  // the widgets' values
  int model_ = 1;
  char model_file_[256] = {};
  std::array<double, sim::kMaxLiveNumbers> numbers_{};  // each live number's field (sim::live_numbers())
};

}  // namespace enact::viewer
