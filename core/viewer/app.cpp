#include "core/viewer/app.h"

#include <imgui.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <thread>

#include "core/graph/temp_folder.h"
#include "core/rt/clock.h"
#include "core/viewer/draw.h"
#include "core/viewer/link.h"
#include "core/viewer/panels.h"
#include "core/viewer/playback.h"
#include "core/viewer/scene_geometry.h"
#include "core/viewer/window.h"

namespace enact::viewer {
namespace {

// what a snapshot showed, for people and tests
void report_snapshot(const ViewerOptions& o, const ViewModel& model, const SceneGeometry& scene, int w, int h) {
  const TaskView& t = model.task();
  std::printf("enact-viewer: snapshot %s (%d x %d), ", o.snapshot.c_str(), w, h);
  if (!scene.name.empty() && scene.task_surface.empty()) {
    std::printf("no task in this scene");
  } else {
    std::printf("task: falls %d, trial %.1f s (%s)", t.falls, static_cast<double>(t.time_ns) * 1e-9, t.completed ? "completed" : t.running ? "running" : "stopped");
  }
  if (model.has_scene()) {
    const msgs::SceneState& s = model.scene();
    std::uint32_t contact = 0;
    for (int i = 0; i < s.in_contact_size(); ++i) contact |= s.in_contact(i) ? 1u << i : 0u;
    std::printf(": scene t %.6f s, body %.6f %.6f %.6f m, contact mask 0x%x, model %s", static_cast<double>(s.header().stamp_ns()) * 1e-9,
                s.body_position().x(), s.body_position().y(), s.body_position().z(), contact, s.model().c_str());
  } else {
    std::printf(": no scene");
  }
  std::printf("\n");
  std::fflush(stdout);
}

// the scene drawn and the controls checked against it: from --scene, else from what the
// graph (or the recording) names, once it does
class SceneInUse {
 public:
  explicit SceneInUse(const ViewerOptions& o) : fixed_(!o.scene.empty()), sim_(o.sim) {
    if (fixed_) load(o.scene, sim_.empty() ? "sim" : sim_);
    else controls_ = std::make_unique<Controls>(sim_.empty() ? "sim" : sim_, "");
  }

  // a scene named by the graph or the recording: loaded when new (and no --scene)
  void offer(const std::optional<NamedScene>& named) {
    if (fixed_ || !named || named == in_use_) return;
    in_use_ = named;
    load(files_.put("scene", "scene.yaml", named->data, named->beside), sim_.empty() ? named->sim : sim_);
  }

  const SceneGeometry& geometry() const { return geometry_; }
  Controls& controls() { return *controls_; }

 private:
  void load(const std::string& path, const std::string& sim) {
    geometry_ = load_geometry(path);
    controls_ = std::make_unique<Controls>(sim, path);
  }

  bool fixed_;
  std::string sim_;
  std::optional<NamedScene> in_use_;
  graph::TempFolder files_;
  SceneGeometry geometry_;
  std::unique_ptr<Controls> controls_;
};

// the live graph: follow it, take what arrived, send what the experimenter asked for
void live_frame(GraphLink& link, ViewModel& model, SceneInUse& scene, std::int64_t now, const Layout& l, const std::vector<char>& keys) {
  if (link.follow(now)) {
    model.clear();
    const std::string what = link.endpoint().empty() ? "the graph ended; waiting for " + link.describe() : "attached to " + link.describe();
    model.note(what);
    std::fprintf(stderr, "enact-viewer: %s\n", what.c_str());
  }
  Controls& controls = scene.controls();
  for (const graph::ParamAnswer& a : link.receive(model, now)) {
    model.on_answer(a);
    controls.answered(a);
  }
  scene.offer(model.graph_scene());
  // the pre-check at the rate of the node that runs the simulator
  if (model.has_scene()) {
    const auto it = model.nodes().find(model.scene().header().source());
    if (it != model.nodes().end()) scene.controls().set_rate(it->second.status.rate_hz());
  }
  task_window(l.task, model, now, link.endpoint().empty() ? link.describe() : link.endpoint(), scene.geometry().task_surface);
  status_window(l.status, model, now);
  std::vector<msgs::ParamUpdate> requests = scene.controls().draw(l.controls, model);
  for (const char key : keys) {
    if (const auto action = key_action(key)) {
      for (const msgs::ParamUpdate& u : scene.controls().on_key(*action, model)) requests.push_back(u);
    }
  }
  for (const msgs::ParamUpdate& u : requests) {
    if (const std::uint64_t id = link.send(u)) scene.controls().sent(id, u);
    else model.note(u.name() + ": not sent (no graph yet)");
  }
}

// a recording: the timeline moves the model
void recording_frame(Playback& playback, ViewModel& model, const std::string& surface, std::int64_t wall_ns, const Layout& l, const std::vector<char>& keys) {
  for (const char key : keys) playback.on_key(key, model);
  playback.advance(wall_ns, model);
  task_window(l.task, model, playback.clock_ns(), "", surface, playback.path());
  status_window(l.status, model, playback.clock_ns());
  playback.draw(l.controls, model);
}

}  // namespace

int run_viewer(const ViewerOptions& o) {
  // a recording is read (and refused) before any window opens
  std::unique_ptr<Playback> playback = o.recording.empty() ? nullptr : std::make_unique<Playback>(o.recording);
  SceneInUse scene(o);
  Window window("enact viewer", o.width, o.height, !o.snapshot.empty());
  ViewModel model;
  std::unique_ptr<GraphLink> link = playback ? nullptr : std::make_unique<GraphLink>(o.graph, "viewer", o.keys);
  if (link && !link->endpoint().empty()) std::fprintf(stderr, "enact-viewer: attached to %s\n", link->describe().c_str());
  if (playback) {
    scene.offer(playback->scene());
    playback->seek(o.at_s >= 0.0 ? static_cast<std::int64_t>(o.at_s * 1e9) : 0, model);
    playback->set_playing(o.at_s < 0.0);
  }
  const std::int64_t frame_ns = static_cast<std::int64_t>(1e9 / o.fps);
  const std::int64_t start = rt::now_ns();
  std::int64_t last = start;
  std::vector<char> keys;
  for (;;) {
    const std::int64_t now = rt::now_ns();
    keys.clear();
    if (!window.poll(keys)) return 0;
    window.begin_frame();
    const Layout l = layout(static_cast<float>(window.width()), static_cast<float>(window.height()));
    if (playback) recording_frame(*playback, model, scene.geometry().task_surface, now - last, l, keys);
    else live_frame(*link, model, scene, now, l, keys);
    last = now;
    // the scene, into the background
    ImDrawList& dl = *ImGui::GetBackgroundDrawList();
    draw_top_view(dl, l.top_view, scene.geometry(), model);
    draw_side_view(dl, l.side_view, scene.geometry(), model);
    draw_pins(dl, l.pins, model);
    draw_forces(dl, l.forces, scene.geometry(), model);
    plot_window(l.plot, model);
    // a snapshot ends the run; the frames before it are not drawn
    if (!o.snapshot.empty()) {
      if (now - start < static_cast<std::int64_t>(o.after_s * 1e9)) {
        window.skip_frame();
      } else if (!window.end_frame(o.snapshot)) {
        std::fprintf(stderr, "enact-viewer: error: cannot write %s\n", o.snapshot.c_str());
        return 1;
      } else {
        report_snapshot(o, model, scene.geometry(), window.width(), window.height());
        return 0;
      }
    } else {
      window.end_frame();
    }
    const std::int64_t left = now + frame_ns - rt::now_ns();
    if (left > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(left));
  }
}

}  // namespace enact::viewer
