#include "core/viewer/app.h"

#include <imgui.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "core/rt/clock.h"
#include "core/viewer/draw.h"
#include "core/viewer/link.h"
#include "core/viewer/panels.h"
#include "core/viewer/scene_geometry.h"
#include "core/viewer/window.h"

namespace enact::viewer {
namespace {

// frames per second the viewer draws at most (the scene comes at 60 Hz)
constexpr std::int64_t kFrame_ns = 16'666'667;

// what a snapshot showed, for people and tests
void report_snapshot(const ViewerOptions& o, const ViewModel& model, int w, int h) {
  std::printf("enact-viewer: snapshot %s (%d x %d)", o.snapshot.c_str(), w, h);
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

}  // namespace

int run_viewer(const ViewerOptions& o) {
  const SceneGeometry geometry = load_geometry(o.scene);
  Window window("enact viewer", o.width, o.height, !o.snapshot.empty());
  GraphLink link(o.attach, "viewer");
  ViewModel model;
  Controls controls(o.sim, o.scene);
  const std::int64_t start = rt::now_ns();
  std::vector<char> keys;
  for (;;) {
    const std::int64_t now = rt::now_ns();
    keys.clear();
    if (!window.poll(keys)) return 0;
    // the graph: follow the attach file, take what arrived
    if (link.follow(now)) {
      model.clear();
      model.note("attaching to " + link.endpoint());
    }
    for (const graph::ParamAnswer& a : link.receive(model, now)) {
      model.on_answer(a);
      controls.answered(a);
    }
    // the pre-check at the rate of the node that runs the simulator
    if (model.has_scene()) {
      const auto it = model.nodes().find(model.scene().header().source());
      if (it != model.nodes().end()) controls.set_rate(it->second.status.rate_hz());
    }
    // draw
    window.begin_frame();
    const Layout l = layout(static_cast<float>(window.width()), static_cast<float>(window.height()));
    ImDrawList& dl = *ImGui::GetBackgroundDrawList();
    draw_top_view(dl, l.top_view, geometry, model);
    draw_side_view(dl, l.side_view, geometry, model);
    draw_pins(dl, l.pins, model);
    draw_forces(dl, l.forces, geometry, model);
    plot_window(l.plot, model);
    task_window(l.task, model, now, link.describe());
    status_window(l.status, model, now);
    std::vector<msgs::ParamUpdate> requests = controls.draw(l.controls, model);
    for (const char key : keys) {
      if (const auto action = key_action(key)) {
        for (const msgs::ParamUpdate& u : controls.on_key(*action, model)) requests.push_back(u);
      }
    }
    for (const msgs::ParamUpdate& u : requests) {
      if (const std::uint64_t id = link.send(u)) controls.sent(id, u);
      else model.note(u.name() + ": not sent (no graph yet)");
    }
    // a snapshot ends the run
    if (!o.snapshot.empty() && now - start >= static_cast<std::int64_t>(o.after_s * 1e9)) {
      if (!window.end_frame(o.snapshot)) {
        std::fprintf(stderr, "enact-viewer: error: cannot write %s\n", o.snapshot.c_str());
        return 1;
      }
      report_snapshot(o, model, window.width(), window.height());
      return 0;
    }
    window.end_frame();
    const std::int64_t left = now + kFrame_ns - rt::now_ns();
    if (left > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(left));
  }
}

}  // namespace enact::viewer
