#include "core/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "core/config/yaml.h"
#include "core/devices/device_profile.h"
#include "core/physics/scene.h"

namespace enact::sim {
namespace {

// a contact normal this close to vertical is the top surface
constexpr double kTopNormalZ = 0.7;

// a re-entering point's deepest contact still pushes along the same face
constexpr double kSameFaceCos = 0.999;

// whether a change alters the force law of the body (pins-only and trial changes do not).
// A model or threshold change re-applies the computer model to every point, which would wipe
// the re-entry depths of a change still settling: while `reentering`, it is one
bool changes_force_law(const ParamChange& c, const LiveTarget& now, bool reentering) {
  switch (c.kind) {
    case ParamKind::model:
      return reentering || c.model.force_grid_mask != now.cm.force_grid_mask || c.model.force_center != now.cm.force_center ||
             c.model.threshold_m != now.cm.threshold_m;
    case ParamKind::number: {
      const LiveNumber& n = live_numbers()[c.number];
      switch (n.law) {
        case LawChange::none: return false;
        case LawChange::always: return true;
        case LawChange::if_new: return reentering || c.value != n.get(now.model, now.cm, now.params);
      }
      return true;
    }
    case ParamKind::reset:
    case ParamKind::reposition: return true;
    case ParamKind::trial_start:
    case ParamKind::trial_stop: return false;
  }
  return true;
}

}  // namespace

int Simulator::grid_masses() const {
  return model_.proxies.empty() ? 0 : model_.proxies[0].rows * model_.proxies[0].cols;
}

void Simulator::configure(const SimParams& params) {
  params_ = params;
  reengage_ = Reengagement(params.reengage_s);
  live_changed_ = 0;
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
  // the live numbers given at start: planned as a live change of the scene as loaded is (the
  // same ranges and stability envelope, the same refusals), then set
  if (std::any_of(params.live_at_start.begin(), params.live_at_start.end(), [](const auto& v) { return v.has_value(); })) {
    ParamPlanner planner(*this);
    LiveTarget live{model_, cm_, params_};
    for (std::size_t n = 0; n < live_numbers().size(); ++n) {
      const std::optional<double>& v = params.live_at_start[n];
      if (!v) continue;
      const ParamPlan plan = planner.plan(live_numbers()[n].name, ParamValue{*v, std::nullopt, std::nullopt}, 0);
      if (!plan.accepted) throw config::Error(plan.reason);
      live_numbers()[n].set(live, *v);
      planner.follow(*this);
    }
  }
  stability_ = physics::analyze_stability(model_);
  const std::string unstable = physics::instability_message(model_, stability_);
  if (!unstable.empty() && !params.force) throw config::Error(unstable);
  tactile_.configure(params.tactile, model_.rate_hz);
  task_ = task::BridgeTask(params.task);
  top_pairs_.clear();
  if (!model_.task_surface.empty()) {
    const int surface = model_.find_object(model_.task_surface);
    std::vector<task::Point2> line;
    for (const auto& p : model_.task_path.centerline_m) line.push_back({p.x, p.y});
    path_ = task::Polyline(line);
    for (std::size_t i = 0; i < model_.contacts.size(); ++i) {
      const physics::ContactPair& c = model_.contacts[i];
      if (c.object == surface && model_.points[c.point].proxy >= 0) top_pairs_.push_back(static_cast<int>(i));
    }
  }
  if (!std::isfinite(params.change_ramp_s) || params.change_ramp_s < 0.0) {
    throw config::Error("change_ramp_s " + std::to_string(params.change_ramp_s) + " is out of range\n  fix: give a time >= 0 s, e.g. 0.05");
  }
  // no jolt: the body's points and contact pairs, scratch space, the device's force step limit
  body_points_.clear();
  body_pairs_.clear();
  for (std::size_t i = 0; i < model_.points.size(); ++i) {
    if (is_body_point(model_, static_cast<int>(i))) body_points_.push_back(static_cast<int>(i));
  }
  for (std::size_t c = 0; c < model_.contacts.size(); ++c) {
    if (is_body_point(model_, model_.contacts[c].point)) body_pairs_.push_back(static_cast<int>(c));
  }
  felt_n_.assign(model_.points.size(), 0.0);
  felt_depth_m_.assign(model_.points.size(), 0.0);
  felt_normal_.assign(model_.points.size(), math::Vec3{});
  deepest_pair_.assign(model_.points.size(), -1);
  const auto profile = devices::find_device_profile(model_.device_profile);
  max_step_n_ = profile && profile->max_force_step_n_per_ms > 0.0 ? profile->max_force_step_n_per_ms * model_.dt_s * 1e3 : 0.0;
  late_steps_ns_ = std::llround(2.0 * model_.dt_s * 1e9);
  state_ = physics::make_state(model_);
  lifecycle_ = Lifecycle::inactive;
}

void Simulator::activate(std::int64_t start_ns) {
  if (lifecycle_ == Lifecycle::unconfigured) throw std::logic_error("Simulator::activate before configure");
  haptics::apply(cm_, model_);  // no threshold left from a re-entry
  physics::reset(model_, state_);
  tactile_.reset();
  task_.reset(start_ns);
  trial_running_ = true;
  trial_change_ = TrialChange::none;
  steps_ = 0;
  reentering_ = capture_ = settling_ = false;
  offset_left_ = offset_total_ = 0;
  out_ = {};
  origin_ns_ = -1;
  reengage_.interrupt();  // the force path starts here
  lifecycle_ = Lifecycle::active;
}

void Simulator::deactivate() {
  if (lifecycle_ == Lifecycle::active) lifecycle_ = Lifecycle::inactive;
  out_.force_n = {};
}

// the fields a keyframe holds as the simulator does, one list for save and restore:
// pair(the simulator's, the keyframe's)
template <class S, class K, class F>
void Simulator::pair_fields(S& s, K& k, F&& pair) {
  pair(s.steps_, k.step);
  pair(s.params_.change_ramp_s, k.change_ramp_s);
  pair(s.state_, k.state);
  pair(s.task_, k.task);
  pair(s.trial_running_, k.trial_running);
  pair(s.trial_change_, k.trial_change);
  pair(s.tactile_, k.tactile);
  pair(s.out_.force_n, k.force_n);
  pair(s.from_n_, k.from_n);
  pair(s.reentering_, k.reentering);
  pair(s.capture_, k.capture);
  pair(s.settling_, k.settling);
  pair(s.offset_left_, k.offset_left);
  pair(s.offset_total_, k.offset_total);
  pair(s.reentry_step_m_, k.reentry_step_m);
  pair(s.felt_depth_m_, k.felt_depth_m);
  pair(s.felt_normal_, k.felt_normal);
  pair(s.reengage_, k.reengage);
  pair(s.origin_ns_, k.origin_ns);
  pair(s.sample_ns_, k.sample_ns);
  pair(s.live_values_, k.live_values);
  pair(s.live_changed_, k.live_changed);
}

void Simulator::save(Keyframe& k) const {
  pair_fields(*this, k, [](const auto& from, auto& to) { to = from; });
  // the parameters in force: the computer model, each contact pair's and each point's
  k.model = to_change(cm_);
  k.stiffness_n_per_m.resize(model_.contacts.size());
  k.damping_n_s_per_m.resize(model_.contacts.size());
  for (std::size_t c = 0; c < model_.contacts.size(); ++c) {
    k.stiffness_n_per_m[c] = model_.contacts[c].stiffness_n_per_m;
    k.damping_n_s_per_m[c] = model_.contacts[c].damping_n_s_per_m;
  }
  k.threshold_m.resize(model_.points.size());
  k.feeds_device.resize(model_.points.size());
  for (std::size_t p = 0; p < model_.points.size(); ++p) {
    k.threshold_m[p] = model_.points[p].contact_threshold_m;
    k.feeds_device[p] = model_.points[p].feeds_device;
  }
}

void Simulator::restore(const Keyframe& k) {
  if (lifecycle_ == Lifecycle::unconfigured) throw std::logic_error("Simulator::restore before configure");
  out_ = {};
  pair_fields(*this, k, [](auto& to, const auto& from) { to = from; });
  assign(cm_, k.model);
  // the live numbers changed before it, then each contact's and point's values exactly
  LiveTarget live{model_, cm_, params_};
  for (std::size_t n = 0; n < live_numbers().size(); ++n) {
    if (live_changed_ & (1u << n)) live_numbers()[n].set(live, live_values_[n]);
  }
  for (std::size_t c = 0; c < model_.contacts.size(); ++c) {
    model_.contacts[c].stiffness_n_per_m = k.stiffness_n_per_m[c];
    model_.contacts[c].damping_n_s_per_m = k.damping_n_s_per_m[c];
  }
  for (std::size_t p = 0; p < model_.points.size(); ++p) {
    model_.points[p].contact_threshold_m = k.threshold_m[p];
    model_.points[p].feeds_device = k.feeds_device[p] != 0;
  }
  lifecycle_ = Lifecycle::active;
}

void Simulator::set_computer_model(const haptics::ComputerModel& cm) {
  cm_ = cm;
  haptics::apply(cm_, model_);
}

ParamApplied Simulator::apply(const ParamChange& c, std::int64_t now_ns) {
  LiveTarget live{model_, cm_, params_};
  const bool law = changes_force_law(c, live, reentering_);
  if (law) keep_felt_forces();
  switch (c.kind) {
    case ParamKind::model:
      assign(cm_, c.model);
      haptics::apply(cm_, model_);
      break;
    case ParamKind::number:
      live_numbers()[c.number].set(live, c.value);
      live_values_[c.number] = c.value;
      live_changed_ |= 1u << c.number;
      break;
    case ParamKind::reset:
      // model, pins and task from the start: a new trial
      physics::reset(model_, state_);
      tactile_.reset();
      trial_change_ = TrialChange::start;
      break;
    case ParamKind::reposition:
      // the body is about to jump back to the start: forget the faces it entered through
      physics::reset(model_, state_);
      break;
    case ParamKind::trial_start: trial_change_ = TrialChange::start; break;
    case ParamKind::trial_stop: trial_change_ = TrialChange::stop; break;
  }
  if (law) {
    reenter_contacts(c.kind == ParamKind::reset || c.kind == ParamKind::reposition);
    capture_ = true;
  }
  return {c.request_id, c.kind, now_ns, steps_ + 1};
}

void Simulator::find_deepest() {
  for (const int p : body_points_) deepest_pair_[p] = -1;
  for (const int c : body_pairs_) {
    const physics::ContactState& cs = state_.contacts[c];
    int& deepest = deepest_pair_[model_.contacts[c].point];
    if (cs.active && (deepest < 0 || cs.depth_m > state_.contacts[deepest].depth_m)) deepest = c;
  }
}

void Simulator::keep_felt_forces() {
  // the elastic force each point gave the device at the last step (its deepest contact)
  find_deepest();
  for (const int p : body_points_) {
    const int c = deepest_pair_[p];
    const physics::Point& point = model_.points[p];
    felt_n_[p] = c < 0 || !point.feeds_device ? 0.0 : model_.contacts[c].stiffness_n_per_m * std::max(0.0, state_.contacts[c].depth_m - point.contact_threshold_m);
  }
}

void Simulator::reenter_contacts(bool from_scratch) {
  // each point in contact counts the new law from the depth where it keeps its felt force
  // (from where it is if it gave none); contacts cleared: from where the next step finds them
  reentering_ = false;
  // rising back at most as fast as the device's force step limit allows, every point pushing
  double stiffness_n_per_m = 0.0;
  for (const int p : body_points_) {
    double k = 0.0;
    for (const int c : body_pairs_) k = model_.contacts[c].point == p ? std::max(k, model_.contacts[c].stiffness_n_per_m) : k;
    stiffness_n_per_m += k;
  }
  reentry_step_m_ = params_.reentry_speed_m_per_s * model_.dt_s;
  if (max_step_n_ > 0.0 && stiffness_n_per_m > 0.0) reentry_step_m_ = std::min(reentry_step_m_, max_step_n_ / stiffness_n_per_m);
  for (const int p : body_points_) {
    const int c = deepest_pair_[p];
    double depth_m = cm_.threshold_m;
    if (from_scratch) {
      depth_m = std::numeric_limits<double>::infinity();
    } else if (c >= 0) {
      const double k = model_.contacts[c].stiffness_n_per_m;
      depth_m = state_.contacts[c].depth_m - (felt_n_[p] > 0.0 && k > 0.0 ? felt_n_[p] / k : 0.0);
    }
    model_.points[p].contact_threshold_m = std::max(cm_.threshold_m, depth_m);
    felt_depth_m_[p] = c < 0 ? 0.0 : std::max(0.0, state_.contacts[c].depth_m - model_.points[p].contact_threshold_m);
    felt_normal_[p] = c < 0 ? math::Vec3{} : state_.contacts[c].normal;
    reentering_ = reentering_ || model_.points[p].contact_threshold_m > cm_.threshold_m;
  }
}

void Simulator::follow_reentry() {
  // a re-entry depth follows its point back out, never in, down to the model's threshold; and
  // whatever the point does (a deeper push, its deepest contact turning to another face), the
  // depth it feels beyond it grows by at most one re-entry step per step, from zero on a new face
  find_deepest();
  reentering_ = false;
  for (const int p : body_points_) {
    const int c = deepest_pair_[p];
    const double depth_m = c < 0 ? 0.0 : state_.contacts[c].depth_m;
    const math::Vec3 normal = c < 0 ? math::Vec3{} : state_.contacts[c].normal;
    const double felt_m = math::dot(normal, felt_normal_[p]) > kSameFaceCos ? felt_depth_m_[p] : 0.0;
    double& threshold_m = model_.points[p].contact_threshold_m;
    threshold_m = std::max({cm_.threshold_m, std::min(threshold_m - reentry_step_m_, depth_m), depth_m - felt_m - reentry_step_m_});
    felt_depth_m_[p] = std::max(0.0, depth_m - threshold_m);
    felt_normal_[p] = normal;
    reentering_ = reentering_ || threshold_m > cm_.threshold_m;
  }
}

math::Vec3 Simulator::blend(const math::Vec3& model_force_n) {
  const bool changing = capture_ || offset_left_ > 0 || reentering_ || settling_;
  if (capture_) {
    // from what the device felt before the change to the new law's force, over the ramp
    capture_ = false;
    from_n_ = out_.force_n;
    offset_total_ = offset_left_ = static_cast<std::int64_t>(std::max(1.0, std::ceil(params_.change_ramp_s * model_.rate_hz)));
  }
  // the force felt before the change was the body pressing on something: once no body point
  // touches anything it ends (at the step limit), never pushing a hand that left the surface
  // (it pushed a hand 4 mm up over 50 ms, which fell back at 15 N: hostile burst seed 23)
  if (offset_left_ > 0 && std::none_of(body_points_.begin(), body_points_.end(), [this](int p) { return state_.in_contact[p] != 0; })) {
    offset_left_ = 0;
  }
  math::Vec3 force_n = model_force_n;
  if (offset_left_ > 0) {
    const double share = static_cast<double>(offset_left_) / static_cast<double>(offset_total_);
    --offset_left_;
    force_n = model_force_n * (1.0 - share) + from_n_ * share;
  }
  // while a change settles, the force never steps by more than the device profile allows
  const math::Vec3 step_n = force_n - out_.force_n;
  const double size_n = math::norm(step_n);
  settling_ = changing && max_step_n_ > 0.0 && size_n > max_step_n_;
  if (settling_) force_n = out_.force_n + step_n * (max_step_n_ / size_n);
  return force_n;
}

const StepOutput& Simulator::step(std::int64_t time_ns, const math::Vec3& device_position_m) {
  if (lifecycle_ != Lifecycle::active) {
    out_ = {};
    return out_;
  }
  // a trial a change started begins at the first step that uses it
  if (trial_change_ == TrialChange::start) {
    task_.reset(time_ns);
    trial_running_ = true;
  }
  const std::uint64_t faults = state_.faults;
  state_.proxy_position_m[0] = device_position_m;
  physics::step(model_, state_);
  ++steps_;
  out_.fault = state_.faults != faults;
  if (out_.fault) {
    // a fault's zero force is not blended
    capture_ = settling_ = false;
    offset_left_ = 0;
  }
  out_.force_n = out_.fault ? state_.proxy_force_n[0] : blend(state_.proxy_force_n[0]);
  if (reentering_) follow_reentry();
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
    const math::Vec3& centre = state_.x[body.point];
    out_.progress = path_.project(centre.x, centre.y).fraction;
    out_.event = trial_running_ ? task_.update(time_ns, out_.on_top, out_.progress) : task::TaskEvent{};
  }
  // a trial a change stopped ends with the first step that uses it
  if (trial_change_ == TrialChange::stop) trial_running_ = false;
  trial_change_ = TrialChange::none;
  return out_;
}

const StepOutput& Simulator::step_sample(std::int64_t sample_ns, const math::Vec3& device_position_m, bool cut) {
  if (origin_ns_ < 0) {
    origin_ns_ = sample_ns;
  } else if (const std::int64_t gap_ns = sample_ns - sample_ns_; gap_ns > std::max(kLateSample_ns, late_steps_ns_)) {
    reengage_.late(state_.proxy_position_m[0], gap_ns);
  }
  sample_ns_ = sample_ns;
  if (cut) reengage_.interrupt();
  const std::int64_t t_ns = sample_ns - origin_ns_;
  step(t_ns, reengage_.position(*this, t_ns, device_position_m));
  if (out_.event.kind != task::TaskEventKind::none) out_.event.time_ns += origin_ns_;  // on the device's clock
  return out_;
}

std::string Simulator::summary() const {
  char line[256];
  std::snprintf(line, sizeof line, "re-synchronised with the device %llu time%s (largest offset %.1f mm)", static_cast<unsigned long long>(reengage_.count()),
                reengage_.count() == 1 ? "" : "s", reengage_.largest_offset_m() * 1e3);
  if (const std::uint64_t late = reengage_.late_count(); late > 0) {
    const std::size_t n = std::strlen(line);
    std::snprintf(line + n, sizeof line - n, "; %llu late sample%s held at the depth before (longest gap %.1f ms, largest offset %.1f mm)",
                  static_cast<unsigned long long>(late), late == 1 ? "" : "s", static_cast<double>(reengage_.longest_gap_ns()) * 1e-6,
                  reengage_.largest_late_offset_m() * 1e3);
  }
  // a scene without a task has no falls and no progress to count
  if (!has_task()) return line;
  const task::Metrics m = metrics();
  char task_line[96];
  std::snprintf(task_line, sizeof task_line, "task: falls %d, progress %.2f%s; ", m.falls, m.progress, m.completed ? " (completed)" : "");
  return task_line + std::string(line);
}

}  // namespace enact::sim
