#include "core/viewer/playback.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

#include "core/config/yaml.h"
#include "core/graph/topics.h"
#include "core/record/reader.h"
#include "msgs/node_status.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"

namespace enact::viewer {
namespace {

constexpr std::int64_t kStep_ns = 5'000'000'000;  // a seek key's step
const double kSpeeds[] = {0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 10.0};

}  // namespace

Playback::Playback(const std::string& path) : path_(path) {
  record::Reader r(path);
  // the viewer's topics, with the type they must have
  const std::pair<const char*, Topic> wanted[] = {{graph::kSceneState, Topic::scene}, {graph::kTaskEvent, Topic::event},
                                                  {graph::kNodeStatus, Topic::status}, {graph::kTactileShown, Topic::shown}};
  r.for_each([&](const record::Message& m) {
    for (const auto& [topic, which] : wanted) {
      if (m.topic == topic) items_.push_back({m.log_time_ns, which, std::string(m.data)});
    }
    return true;
  });
  if (items_.empty()) {
    throw config::Error(path + ": no sim/scene, task/event, node/status or tactile/shown messages: nothing to show\n"
                               "  fix: record those topics (enact record --all)");
  }
  std::stable_sort(items_.begin(), items_.end(), [](const Item& a, const Item& b) { return a.time_ns < b.time_ns; });
  start_ns_ = items_.front().time_ns;
  duration_ns_ = items_.back().time_ns - start_ns_;
  // the scene file the logger attached under its parameter's name
  scene_ = find_scene(r.attachments(), record::name_of, record::data_of);
}

void Playback::set_speed(double speed) { speed_ = std::clamp(speed, 0.1, 10.0); }

void Playback::play_until(std::int64_t clock_ns, ViewModel& model) {
  msgs::SceneState scene;
  msgs::TaskEvent event;
  msgs::NodeStatus status;
  msgs::TactileShown shown;
  for (; next_ < items_.size() && items_[next_].time_ns <= clock_ns; ++next_) {
    const Item& it = items_[next_];
    const int size = static_cast<int>(it.data.size());
    switch (it.topic) {
      case Topic::scene:
        if (scene.ParseFromArray(it.data.data(), size)) model.on_scene(scene);
        break;
      case Topic::event:
        if (event.ParseFromArray(it.data.data(), size)) model.on_event(event);
        break;
      case Topic::status:
        if (status.ParseFromArray(it.data.data(), size)) model.on_status(status, it.time_ns);
        break;
      case Topic::shown:
        if (shown.ParseFromArray(it.data.data(), size)) model.on_shown(shown);
        break;
    }
  }
}

void Playback::seek(std::int64_t position_ns, ViewModel& model) {
  position_ns = std::clamp<std::int64_t>(position_ns, 0, duration_ns_);
  // backward: the model holds history (trail, falls): replay from the start
  if (position_ns < position_ns_ || next_ == 0) {
    model.clear();
    next_ = 0;
  }
  position_ns_ = position_ns;
  play_until(clock_ns(), model);
}

void Playback::advance(std::int64_t wall_ns, ViewModel& model) {
  if (!playing_) return;
  seek(position_ns_ + static_cast<std::int64_t>(static_cast<double>(wall_ns) * speed_), model);
  if (position_ns_ >= duration_ns_) playing_ = false;
}

void Playback::on_key(char key, ViewModel& model) {
  switch (key) {
    case ' ': playing_ = !playing_; break;
    case ',': seek(position_ns_ - kStep_ns, model); break;
    case '.': seek(position_ns_ + kStep_ns, model); break;
    case '<': set_speed(speed_ / 2.0); break;
    case '>': set_speed(speed_ * 2.0); break;
    default: break;
  }
}

void Playback::draw(const Rect& r, ViewModel& model) {
  ImGui::SetNextWindowPos({r.x0, r.y0});
  ImGui::SetNextWindowSize({r.width(), r.height()});
  ImGui::Begin("recording", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings);
  ImGui::TextWrapped("%s", path_.c_str());
  ImGui::Text("%.2f s of %.2f s", static_cast<double>(position_ns_) * 1e-9, static_cast<double>(duration_ns_) * 1e-9);
  if (ImGui::Button(playing_ ? "pause" : "play")) {
    if (!playing_ && position_ns_ >= duration_ns_) seek(0, model);
    playing_ = !playing_;
  }
  ImGui::SameLine();
  if (ImGui::Button("<< 5 s")) seek(position_ns_ - kStep_ns, model);
  ImGui::SameLine();
  if (ImGui::Button("5 s >>")) seek(position_ns_ + kStep_ns, model);
  // the timeline
  float seconds = static_cast<float>(static_cast<double>(position_ns_) * 1e-9);
  ImGui::SetNextItemWidth(-1.0f);
  if (ImGui::SliderFloat("##timeline", &seconds, 0.0f, static_cast<float>(static_cast<double>(duration_ns_) * 1e-9), "%.2f s")) {
    seek(static_cast<std::int64_t>(static_cast<double>(seconds) * 1e9), model);
  }
  char current[16];
  std::snprintf(current, sizeof current, "%gx", speed_);
  ImGui::SetNextItemWidth(100);
  if (ImGui::BeginCombo("speed", current)) {
    for (const double s : kSpeeds) {
      char label[16];
      std::snprintf(label, sizeof label, "%gx", s);
      if (ImGui::Selectable(label, speed_ == s)) set_speed(s);
    }
    ImGui::EndCombo();
  }
  ImGui::Separator();
  ImGui::TextWrapped("keys: space play / pause, ',' '.' 5 s back / on, '<' '>' speed / 2, x 2");
  ImGui::Separator();
  for (std::size_t i = model.log().size(); i-- > 0;) ImGui::TextWrapped("%s", model.log()[i].c_str());
  ImGui::End();
}

}  // namespace enact::viewer
