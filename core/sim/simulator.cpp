#include "core/sim/simulator.h"

#include <stdexcept>

#include "core/config/yaml.h"
#include "core/physics/scene.h"

namespace enact::sim {
namespace {

// a contact normal this close to vertical is the top surface
constexpr double kTopNormalZ = 0.7;

}  // namespace

int Simulator::grid_masses() const {
  return model_.proxies.empty() ? 0 : model_.proxies[0].rows * model_.proxies[0].cols;
}

void Simulator::configure(const SimParams& params) {
  params_ = params;
  model_ = physics::load_scene(params.scene);
  if (params.rate_hz != 0.0) {
    if (params.rate_hz < 1.0 || params.rate_hz > 44000.0) throw config::Error("rate " + std::to_string(params.rate_hz) + " Hz is out of range\n  fix: use a rate from 1 to 44000 Hz");
    model_.set_rate(params.rate_hz);
  }
  if (model_.proxies.empty()) throw config::Error(params.scene + ": the scene has no body: nothing for a device to drive\n  fix: add a body: section");
  cm_ = haptics::resolve_computer_model(params.model, grid_masses());
  // room for any name a live change carries: switching models between steps never allocates
  cm_.name.reserve(kMaxModelName + 1);
  haptics::apply(cm_, model_);
  stability_ = physics::analyze_stability(model_);
  const std::string unstable = physics::instability_message(model_, stability_);
  if (!unstable.empty() && !params.force) throw config::Error(unstable);
  tactile_.configure(params.tactile, model_.rate_hz);
  task_ = task::BridgeTask(params.task);
  top_pairs_.clear();
  if (!model_.task_surface.empty()) {
    const int surface = model_.find_object(model_.task_surface);
    std::vector<task::Point2> line;
    for (const auto& p : model_.objects[surface].path.centerline_m) line.push_back({p.x, p.y});
    path_ = task::Polyline(line);
    for (std::size_t i = 0; i < model_.contacts.size(); ++i) {
      const physics::ContactPair& c = model_.contacts[i];
      if (c.object == surface && model_.points[c.point].kind == physics::PointKind::kinematic) top_pairs_.push_back(static_cast<int>(i));
    }
  }
  state_ = physics::make_state(model_);
  lifecycle_ = Lifecycle::inactive;
}

void Simulator::activate(std::int64_t start_ns) {
  if (lifecycle_ == Lifecycle::unconfigured) throw std::logic_error("Simulator::activate before configure");
  physics::reset(model_, state_);
  tactile_.reset();
  task_.reset(start_ns);
  trial_running_ = true;
  out_ = {};
  lifecycle_ = Lifecycle::active;
}

void Simulator::deactivate() {
  if (lifecycle_ == Lifecycle::active) lifecycle_ = Lifecycle::inactive;
  out_.force_n = {};
}

void Simulator::set_computer_model(const haptics::ComputerModel& cm) {
  cm_ = cm;
  haptics::apply(cm_, model_);
}

ParamApplied Simulator::apply(const ParamChange& c, std::int64_t time_ns, std::int64_t now_ns) {
  switch (c.kind) {
    case ParamKind::model:
      assign(cm_, c.model);
      haptics::apply(cm_, model_);
      break;
    case ParamKind::threshold:
      cm_.threshold_m = c.value;
      haptics::apply(cm_, model_);
      break;
    case ParamKind::stiffness: set_body_contacts(model_, c.value, std::nullopt); break;
    case ParamKind::damping: set_body_contacts(model_, std::nullopt, c.value); break;
    case ParamKind::reset:
      // model, pins and task from the start: a new trial
      physics::reset(model_, state_);
      tactile_.reset();
      task_.reset(time_ns);
      trial_running_ = true;
      break;
    case ParamKind::reposition:
      // the body is about to jump back to the start: forget the faces it entered through
      physics::reset(model_, state_);
      break;
    case ParamKind::trial_start:
      task_.reset(time_ns);
      trial_running_ = true;
      break;
    case ParamKind::trial_stop: trial_running_ = false; break;
  }
  return {c.request_id, c.kind, now_ns};
}

const StepOutput& Simulator::step(std::int64_t time_ns, const physics::Vec3& device_position_m) {
  if (lifecycle_ != Lifecycle::active) {
    out_ = {};
    return out_;
  }
  const std::uint64_t faults = state_.faults;
  state_.proxy_position_m[0] = device_position_m;
  physics::step(model_, state_);
  out_.fault = state_.faults != faults;
  out_.force_n = state_.proxy_force_n[0];
  // pins and contacts from the same contacts as the force
  const physics::Proxy& body = model_.proxies[0];
  out_.contacts = 0;
  for (int i = 0; i < body.rows * body.cols; ++i) out_.contacts += state_.in_contact[body.first_body + i];
  out_.pins = haptics::pins(cm_, model_, state_);
  out_.frame_due = tactile_.push(out_.pins);
  out_.frame = tactile_.frame();
  // task: contact with the top of the task surface, progress along its path
  out_.on_top = false;
  for (int pair : top_pairs_) {
    const physics::ContactState& c = state_.contacts[pair];
    out_.on_top = out_.on_top || (c.active && c.normal.z > kTopNormalZ);
  }
  if (has_task()) {
    const physics::Vec3& centre = state_.x[body.point];
    out_.progress = path_.project(centre.x, centre.y).fraction;
    out_.event = trial_running_ ? task_.update(time_ns, out_.on_top, out_.progress) : task::TaskEvent{};
  }
  return out_;
}

}  // namespace enact::sim
