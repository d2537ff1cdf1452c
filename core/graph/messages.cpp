#include "core/graph/messages.h"

#include <algorithm>
#include <cmath>

namespace enact::graph {

void set(msgs::Vec3& out, const math::Vec3& v) {
  out.set_x(v.x);
  out.set_y(v.y);
  out.set_z(v.z);
}

math::Vec3 get(const msgs::Vec3& v) { return {v.x(), v.y(), v.z()}; }

std::uint32_t device_faults(std::uint32_t f) {
  using devices::DeviceFault;
  std::uint32_t out = 0;
  if (devices::has(f, DeviceFault::clamped) || devices::has(f, DeviceFault::nonfinite_command)) out |= msgs::DEVICE_FAULT_OVER_FORCE;
  if (devices::has(f, DeviceFault::workspace_limit)) out |= msgs::DEVICE_FAULT_OUT_OF_WORKSPACE;
  if (devices::has(f, DeviceFault::device_error)) out |= msgs::DEVICE_FAULT_COMMUNICATION;
  if (devices::has(f, DeviceFault::watchdog)) out |= msgs::DEVICE_FAULT_WATCHDOG;
  return out;
}

bool force_path_cut(std::uint32_t bus_faults) { return (bus_faults & (msgs::DEVICE_FAULT_WATCHDOG | msgs::DEVICE_FAULT_COMMUNICATION)) != 0; }

void fill(msgs::DeviceState& m, const devices::ForceSample& s) {
  m.mutable_header()->set_stamp_ns(s.time_ns);
  set(*m.mutable_position(), s.position_m);
  set(*m.mutable_velocity(), s.velocity_m_per_s);
  m.set_buttons(s.buttons);
  m.set_faults(device_faults(s.faults));
  set(*m.mutable_force(), s.force_n);
}

void fill(msgs::ForceCommand& m, std::uint64_t answered_seq, const math::Vec3& force_n, bool model_fault) {
  m.mutable_header()->set_stamp_ns(0);
  m.set_answered_seq(answered_seq);
  set(*m.mutable_force(), force_n);
  m.set_zero(false);
  m.set_faults(model_fault ? msgs::COMMAND_FAULT_MODEL_UNSTABLE : 0);
}

namespace {

// resize a repeated float field once, then overwrite it
void levels(google::protobuf::RepeatedField<float>& out, int n) {
  if (out.size() != n) out.Resize(n, 0.0f);
}

}  // namespace

void fill(msgs::TactileFrame& m, int rows, int cols, std::uint32_t pins) {
  m.mutable_header()->set_stamp_ns(0);
  m.set_rows(static_cast<std::uint32_t>(rows));
  m.set_cols(static_cast<std::uint32_t>(cols));
  levels(*m.mutable_level(), rows * cols);
  for (int i = 0; i < rows * cols; ++i) m.set_level(i, (pins >> i) & 1u ? 1.0f : 0.0f);
}

void fill(msgs::TactileShown& m, int rows, int cols, const float* shown, std::uint64_t frame_seq, const devices::PinMotion* motion) {
  const int pins = rows * cols;
  m.mutable_header()->set_stamp_ns(0);
  m.set_rows(static_cast<std::uint32_t>(rows));
  m.set_cols(static_cast<std::uint32_t>(cols));
  levels(*m.mutable_level(), pins);
  for (int i = 0; i < pins; ++i) m.set_level(i, shown[i]);
  m.set_frame_seq(frame_seq);
  if (!motion) {
    m.clear_motion();
    return;
  }
  msgs::TactileShown::PinMotion& out = *m.mutable_motion();
  out.set_targets(motion->targets);
  out.set_stroke_ns(motion->rise_ns);
  out.mutable_from_level()->Resize(pins, 0.0);
  out.mutable_from_ns()->Resize(pins, 0);
  for (int i = 0; i < pins; ++i) {
    out.set_from_level(i, motion->strokes[static_cast<std::size_t>(i)].from_level);
    out.set_from_ns(i, motion->strokes[static_cast<std::size_t>(i)].from_ns);
  }
}

bool get(const msgs::TactileShown& m, devices::PinMotion& out) {
  if (!m.has_motion()) return false;
  const msgs::TactileShown::PinMotion& in = m.motion();
  const int pins = std::min(in.from_level_size(), in.from_ns_size());
  if (pins > 32 || !(in.stroke_ns() > 0.0)) return false;
  out = {};
  out.targets = in.targets();
  out.rise_ns = in.stroke_ns();
  for (int i = 0; i < pins; ++i) out.strokes[static_cast<std::size_t>(i)] = {in.from_level(i), in.from_ns(i)};
  return true;
}

void snapshot(const sim::Simulator& s, std::uint32_t pins, const math::Vec3& force_n, SceneSnapshot& out) {
  const physics::State& state = s.state();
  const physics::Proxy& body = s.model().proxies[0];
  // on the graph's clock, as the device states: the device's clock at the model's time 0 (the
  // first sample) plus the model's time; a simulator stepped without samples: the model's time
  out.time_ns = std::max<std::int64_t>(s.origin_ns(), 0) + std::llround(state.time_s * 1e9);
  out.body_m = state.x[body.point];
  out.masses = std::min(body.rows * body.cols, 32);
  out.in_contact = 0;
  for (int i = 0; i < out.masses; ++i) {
    out.contact_force_n[i] = physics::body_contact_force(s.model(), state, body.first_body + i);
    if (state.in_contact[body.first_body + i]) out.in_contact |= 1u << i;
  }
  out.pins = pins;
  out.force_n = force_n;
  out.on_top = s.output().on_top;
  out.progress = s.output().progress;
}

void fill(msgs::SceneState& m, const SceneSnapshot& s, const std::string& model) {
  m.mutable_header()->set_stamp_ns(s.time_ns);
  set(*m.mutable_body_position(), s.body_m);
  while (m.contact_force_size() < s.masses) m.add_contact_force();
  if (m.in_contact_size() != s.masses) m.mutable_in_contact()->Resize(s.masses, false);
  levels(*m.mutable_pin_level(), s.masses);
  for (int i = 0; i < s.masses; ++i) {
    set(*m.mutable_contact_force(i), s.contact_force_n[i]);
    m.set_in_contact(i, (s.in_contact >> i) & 1u);
    m.set_pin_level(i, (s.pins >> i) & 1u ? 1.0f : 0.0f);
  }
  set(*m.mutable_resultant_force(), s.force_n);
  if (m.model() != model) m.set_model(model);
  m.set_on_top(s.on_top);
  m.set_progress(s.progress);
}

void fill(msgs::SimKeyframe& m, const sim::Keyframe& k, const physics::Model& model) {
  m.mutable_header()->set_stamp_ns(k.sample_ns);
  m.set_step(k.step);
  m.set_origin_ns(k.origin_ns);
  m.set_model(k.model.name);
  set(*m.mutable_body_position(), k.state.x[model.proxies[0].point]);
  // the trial as its events told it, on the device clock (0: none)
  const task::BridgeTask::Account a = k.task.account();
  auto on_device = [&](std::int64_t t_ns) { return t_ns < 0 ? 0 : k.origin_ns + t_ns; };
  m.set_trial_start_ns(on_device(a.start_ns));
  m.set_falls(a.falls);
  m.set_closed_out_ns(a.closed_out_ns);
  m.set_fall_since_ns(on_device(a.fall_since_ns));
  m.set_stopped(!k.trial_running && a.end_ns < 0);
  m.set_trial_end_ns(on_device(m.stopped() ? a.last_ns : a.end_ns));
  sim::pack(k, *m.mutable_memory());
}

bool fill(msgs::TaskEvent& m, const task::TaskEvent& e, const std::string& condition) {
  switch (e.kind) {
    case task::TaskEventKind::none: return false;
    case task::TaskEventKind::fall_start: m.set_kind(msgs::TaskEvent::FALL_START); break;
    case task::TaskEventKind::fall_end: m.set_kind(msgs::TaskEvent::FALL_END); break;
    case task::TaskEventKind::completed: m.set_kind(msgs::TaskEvent::TRIAL_END); break;
  }
  m.mutable_header()->set_stamp_ns(0);
  m.set_time_ns(e.time_ns);
  m.set_condition(condition);
  return true;
}

void fill(msgs::NodeStatus& m, const std::string& node, const rt::LoopSummary& loop, std::uint64_t faults, const std::string& last_fault) {
  m.mutable_header()->set_stamp_ns(0);
  m.set_node(node);
  m.set_state(msgs::NodeStatus::ACTIVE);
  m.set_rate_hz(loop.rate_hz);
  m.set_latency_p50_ns(loop.latency_p50_ns);
  m.set_latency_p99_ns(loop.latency_p99_ns);
  m.set_latency_p999_ns(loop.latency_p999_ns);
  m.set_latency_max_ns(loop.latency_max_ns);
  m.set_jitter_p99_ns(loop.jitter_p99_ns);
  m.set_overruns(loop.overruns);
  m.set_faults(faults);
  m.set_last_fault(last_fault);
}

}  // namespace enact::graph
