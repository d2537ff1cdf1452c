#include "core/viewer/panels.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <exception>

#include "core/sim/simulator.h"
#include "core/viewer/draw.h"

namespace enact::viewer {
namespace {

const ImVec4 kGood{0.45f, 0.85f, 0.50f, 1.0f};
const ImVec4 kBad{1.0f, 0.45f, 0.35f, 1.0f};
const ImVec4 kDim{0.60f, 0.62f, 0.66f, 1.0f};

const char* const kPresets[] = {"CM0", "CM1", "CM2", "CM3", "P", "T", "PT"};

// a window that stays where the layout puts it
bool begin_fixed(const char* name, const Rect& r) {
  ImGui::SetNextWindowPos({r.x0, r.y0});
  ImGui::SetNextWindowSize({r.width(), r.height()});
  return ImGui::Begin(name, nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings);
}

sim::ParamValue number(double v) { return {v, std::nullopt, std::nullopt}; }
sim::ParamValue text(const std::string& v) { return {std::nullopt, v, std::nullopt}; }
sim::ParamValue flag(bool v) { return {std::nullopt, std::nullopt, v}; }

// the parameters the pre-check looks at: the live numbers
bool prechecked(const std::string& param) { return sim::find_live_number(param) != nullptr; }

}  // namespace

std::string link_line(LinkState state, const std::string& graph_name, const std::string& where) {
  switch (state) {
    case LinkState::waiting: return "waiting for " + where;
    case LinkState::connected: return "graph '" + graph_name + "' at " + where;
    case LinkState::lost: return "graph '" + graph_name + "' lost (no answer for 3 s)";
  }
  return "";
}

std::string place_line(const TaskView& t, const std::string& surface) {
  if (surface.empty()) return "no task in this scene: nothing is counted";
  return std::string(t.on_top ? "ON the " : "OFF the ") + surface + "  falls " + std::to_string(t.falls) + (t.falling ? " (falling)" : "");
}

void task_window(const Rect& r, const ViewModel& model, std::int64_t now_ns, const std::string& source, const std::string& surface, const std::string& recording) {
  const bool has_task = !surface.empty();
  begin_fixed("task", r);
  if (!recording.empty()) {
    ImGui::TextColored(kGood, "recording %s", recording.c_str());
  } else {
    const LinkState state = model.link(now_ns);
    const ImVec4 colour = state == LinkState::connected ? kGood : state == LinkState::lost ? kBad : kDim;
    ImGui::TextColored(colour, "%s", link_line(state, model.graph_name(), source).c_str());
  }
  ImGui::Separator();
  const TaskView& t = model.task();
  if (model.has_scene()) {
    ImGui::Text("computer model %s", model.scene().model().c_str());
    ImGui::TextColored(!has_task ? kDim : t.on_top ? kGood : kBad, "%s", place_line(t, surface).c_str());
    if (has_task) {
      ImGui::Text("trial %.1f s %s", static_cast<double>(t.time_ns) * 1e-9, t.completed ? "(completed)" : t.running ? "(running)" : "(stopped)");
      char progress[32];
      std::snprintf(progress, sizeof progress, "progress %.0f %%", t.progress * 100.0);
      ImGui::ProgressBar(static_cast<float>(t.progress), {-1.0f, 0.0f}, progress);
    }
  } else {
    ImGui::TextColored(kDim, "no scene yet");
  }
  ImGui::End();
}

void status_window(const Rect& r, const ViewModel& model, std::int64_t now_ns) {
  begin_fixed("nodes (node/status)", r);
  constexpr ImGuiTableFlags flags = ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit;
  if (ImGui::BeginTable("nodes", 11, flags)) {
    for (const char* h : {"node", "rate Hz", "lat p50", "p99", "p99.9", "max", "jitter p99", "overruns", "drops", "faults", "age"}) ImGui::TableSetupColumn(h);
    ImGui::TableHeadersRow();
    for (const auto& [name, row] : model.nodes()) {
      const msgs::NodeStatus& s = row.status;
      std::uint64_t drops = 0;
      for (const auto& t : s.topics()) drops += t.dropped();
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(name.c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%.0f", s.rate_hz());
      for (const std::int64_t ns : {s.latency_p50_ns(), s.latency_p99_ns(), s.latency_p999_ns(), s.latency_max_ns(), s.jitter_p99_ns()}) {
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(format_ns(ns).c_str());
      }
      ImGui::TableNextColumn();
      ImGui::Text("%llu", static_cast<unsigned long long>(s.overruns()));
      ImGui::TableNextColumn();
      ImGui::Text("%llu", static_cast<unsigned long long>(drops));
      ImGui::TableNextColumn();
      if (s.faults() > 0) ImGui::TextColored(kBad, "%llu %s", static_cast<unsigned long long>(s.faults()), s.last_fault().c_str());
      else ImGui::Text("0");
      ImGui::TableNextColumn();
      ImGui::Text("%.1f s", static_cast<double>(now_ns - row.received_ns) * 1e-9);
    }
    ImGui::EndTable();
  }
  if (model.nodes().empty()) ImGui::TextColored(kDim, "no node/status yet (every node sends one a second)");
  ImGui::End();
}

void plot_window(const Rect& r, const ViewModel& model) {
  begin_fixed("force and contacts", r);
  const ImVec2 at = ImGui::GetCursorScreenPos(), room = ImGui::GetContentRegionAvail();
  const float half = room.y / 2;
  const double span_s = static_cast<double>(ViewModel::kHistory) / ViewModel::kSceneRate_hz;
  // oldest first
  auto values = [](const auto& ring) {
    std::vector<float> v(ring.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = ring[i];
    return v;
  };
  const std::vector<float> f = values(model.force_history()), c = values(model.contact_history());
  // |F| on a round scale from 0 N; contacts from 0 to 16
  const double scale_n = round_scale(f.empty() ? 0.0 : static_cast<double>(*std::max_element(f.begin(), f.end())), 0.1);
  char title[96];
  std::snprintf(title, sizeof title, "|F| (N), now %.3f N", f.empty() ? 0.0 : static_cast<double>(f.back()));
  ImDrawList& dl = *ImGui::GetWindowDrawList();
  draw_plot(dl, {at.x, at.y, at.x + room.x, at.y + half - 4}, f, ViewModel::kHistory, scale_n, "N", title, span_s);
  std::snprintf(title, sizeof title, "masses in contact, now %.0f of 16", c.empty() ? 0.0 : static_cast<double>(c.back()));
  draw_plot(dl, {at.x, at.y + half + 4, at.x + room.x, at.y + room.y}, c, ViewModel::kHistory, 16.0, "", title, span_s);
  ImGui::End();
}

std::optional<KeyAction> key_action(char key) {
  switch (key) {
    case '0': return KeyAction::cm0;
    case '1': return KeyAction::cm1;
    case '2': return KeyAction::cm2;
    case '3': return KeyAction::cm3;
    case 'r': return KeyAction::reset;
    case 'p': return KeyAction::reposition;
    case 't': return KeyAction::trial_toggle;
    case '+':
    case '=': return KeyAction::stiffer;
    case '-': return KeyAction::softer;
    case ']': return KeyAction::threshold_up;
    case '[': return KeyAction::threshold_down;
    default: return std::nullopt;
  }
}

Controls::Controls(std::string sim, std::string scene_file) : sim_(std::move(sim)), scene_(std::move(scene_file)) { rebuild(); }

void Controls::set_rate(double rate_hz) {
  if (rate_hz <= 0.0 || rate_hz == rate_hz_) return;
  rate_hz_ = rate_hz;
  rebuild();
}

void Controls::rebuild() {
  // the simulator as the graph configured it, for its planner only; every change applied so far replayed
  try {
    sim::SimParams p;
    p.scene = scene_;
    p.rate_hz = rate_hz_;
    p.force = true;
    sim::Simulator s;
    s.configure(p);
    planner_ = std::make_unique<sim::ParamPlanner>(s);
    for (const auto& [param, value] : applied_) planner_->plan(param, value, 0);
  } catch (const std::exception& e) {
    planner_.reset();
    status_ = std::string("no stability pre-check (the simulator decides): ") + e.what();
  }
  for (std::size_t n = 0; n < sim::live_numbers().size(); ++n) numbers_[n] = planner_ ? planner_->value(sim::live_numbers()[n]) : 0.0;
}

double Controls::stiffness_n_per_m() const { return planner_ ? planner_->stiffness_n_per_m() : 0.0; }
double Controls::damping_n_s_per_m() const { return planner_ ? planner_->damping_n_s_per_m() : 0.0; }
double Controls::threshold_m() const { return planner_ ? planner_->computer_model().threshold_m : 0.0; }

std::optional<msgs::ParamUpdate> Controls::request(const std::string& param, const sim::ParamValue& value) {
  // checked on a copy: the mirror changes only once the simulator applied it
  if (planner_ && prechecked(param)) {
    sim::ParamPlanner trial = *planner_;
    const sim::ParamPlan plan = trial.plan(param, value, 0);
    if (!plan.accepted) {
      status_ = "not sent: " + plan.reason;
      return std::nullopt;
    }
  }
  msgs::ParamUpdate u;
  u.set_name(sim_ + "." + param);
  graph::set_value(u, value);
  status_ = "sent " + u.name();
  return u;
}

void Controls::sent(std::uint64_t id, const msgs::ParamUpdate& update) {
  in_flight_[id] = {update.name().substr(sim_.size() + 1), graph::value_of(update)};
}

void Controls::answered(const graph::ParamAnswer& a) {
  const auto it = in_flight_.find(a.request_id);
  if (it == in_flight_.end()) return;
  if (a.applied) {
    applied_.push_back(it->second);
    if (planner_) planner_->plan(it->second.first, it->second.second, 0);
    status_ = a.name + ": applied";
  } else {
    status_ = a.name + ": refused: " + a.reason;
  }
  in_flight_.erase(it);
}

std::vector<msgs::ParamUpdate> Controls::on_key(KeyAction action, const ViewModel& model) {
  std::optional<msgs::ParamUpdate> u;
  const bool contacts = planner_ != nullptr;
  switch (action) {
    case KeyAction::cm0: u = request("model", text("CM0")); break;
    case KeyAction::cm1: u = request("model", text("CM1")); break;
    case KeyAction::cm2: u = request("model", text("CM2")); break;
    case KeyAction::cm3: u = request("model", text("CM3")); break;
    case KeyAction::reset: u = request("reset", flag(true)); break;
    case KeyAction::reposition: u = request("reposition", flag(true)); break;
    case KeyAction::trial_toggle: u = request("trial", text(model.task().running ? "stop" : "start")); break;
    case KeyAction::stiffer:
      if (contacts) u = request("stiffness_n_per_m", number(stiffness_n_per_m() * 1.25));
      break;
    case KeyAction::softer:
      if (contacts) u = request("stiffness_n_per_m", number(stiffness_n_per_m() / 1.25));
      break;
    case KeyAction::threshold_up:
      if (contacts) u = request("threshold_m", number(threshold_m() + 0.0005));
      break;
    case KeyAction::threshold_down:
      if (contacts) u = request("threshold_m", number(std::max(0.0, threshold_m() - 0.0005)));
      break;
  }
  if (!u && !contacts && (action == KeyAction::stiffer || action == KeyAction::softer || action == KeyAction::threshold_up || action == KeyAction::threshold_down)) {
    status_ = "these keys need the pre-check (the scene file): use the fields";
  }
  return u ? std::vector<msgs::ParamUpdate>{*u} : std::vector<msgs::ParamUpdate>{};
}

std::vector<msgs::ParamUpdate> Controls::draw(const Rect& r, const ViewModel& model) {
  std::vector<msgs::ParamUpdate> out;
  auto add = [&](std::optional<msgs::ParamUpdate> u) {
    if (u) out.push_back(*u);
  };
  begin_fixed("experimenter", r);
  ImGui::Text("computer model: %s", model.has_scene() ? model.scene().model().c_str() : "?");
  ImGui::SetNextItemWidth(90);
  ImGui::Combo("##preset", &model_, kPresets, IM_ARRAYSIZE(kPresets));
  ImGui::SameLine();
  if (ImGui::Button("switch")) add(request("model", text(kPresets[model_])));
  ImGui::SetNextItemWidth(200);
  ImGui::InputTextWithHint("##file", "or a model YAML file", model_file_, sizeof model_file_);
  ImGui::SameLine();
  if (ImGui::Button("load") && model_file_[0]) add(request("model", text(model_file_)));
  ImGui::Separator();
  // a field for each live number, from its declaration
  for (std::size_t n = 0; n < sim::live_numbers().size(); ++n) {
    const sim::LiveNumber& live = sim::live_numbers()[n];
    ImGui::PushID(live.name);
    ImGui::SetNextItemWidth(150);
    ImGui::InputDouble("##value", &numbers_[n], 0.0, 0.0, "%.6g");
    ImGui::SameLine();
    if (ImGui::Button((std::string("set ") + live.name).c_str())) add(request(live.name, number(numbers_[n])));
    ImGui::PopID();
  }
  if (planner_) {
    char now[160];
    std::snprintf(now, sizeof now, "now %.0f N/m, %.3f N s/m, threshold %.2f mm; stable while K T/2 + B <= %.2f N s/m", stiffness_n_per_m(),
                  damping_n_s_per_m(), threshold_m() * 1e3, planner_->passivity_envelope_n_s_per_m());
    ImGui::PushStyleColor(ImGuiCol_Text, kDim);
    ImGui::TextWrapped("%s", now);
    ImGui::PopStyleColor();
  }
  ImGui::Separator();
  if (ImGui::Button("reset")) add(request("reset", flag(true)));
  ImGui::SameLine();
  if (ImGui::Button("reposition")) add(request("reposition", flag(true)));
  ImGui::SameLine();
  if (ImGui::Button("start trial")) add(request("trial", text("start")));
  ImGui::SameLine();
  if (ImGui::Button("stop trial")) add(request("trial", text("stop")));
  ImGui::TextWrapped("%s", status_.c_str());
  ImGui::Separator();
  ImGui::PushStyleColor(ImGuiCol_Text, kDim);
  ImGui::TextWrapped("keys: 0-3 CM0-CM3, r reset, p reposition, t trial start/stop, +/- stiffness x1.25, ]/[ threshold +/-0.5 mm");
  ImGui::PopStyleColor();
  ImGui::Separator();
  for (std::size_t i = model.log().size(); i-- > 0;) ImGui::TextWrapped("%s", model.log()[i].c_str());
  ImGui::End();
  return out;
}

}  // namespace enact::viewer
