#include "core/devices/simulated_force.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/config/format.h"
#include "core/devices/params_error.h"
#include "core/devices/virtual_subject.h"

namespace enact::devices {

SimulatedForceParams held_at_origin(const std::string& profile) {
  SimulatedForceParams p;
  p.profile = profile;
  p.start_m = {0.0, 0.0, 0.0};
  return p;
}
namespace {

using math::Vec3;

constexpr const char* kSimulatedForce = "simulated force device";

// accuracy bounds on a substep: omega dt for the stiffest spring, c dt / m for all damping
// (semi-implicit Euler is stable up to omega dt = 2)
constexpr double kMaxOmegaDt = 0.1;
constexpr double kMaxDampingDt = 0.2;

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// finite and >= 0 (> 0 unless zero_ok)
void check_positive(const char* what, double value, bool zero_ok) {
  if (std::isfinite(value) && (value > 0.0 || (zero_ok && value == 0.0))) return;
  refuse(kSimulatedForce, std::string(what) + " is " + config::number(value),
         std::string("set ") + what + (zero_ok ? " to a finite number >= 0" : " to a finite number > 0"));
}

bool inside(const Vec3& x, const Vec3& lo, const Vec3& hi) {
  return x.x >= lo.x && x.x <= hi.x && x.y >= lo.y && x.y <= hi.y && x.z >= lo.z && x.z <= hi.z;
}

std::string text(const Vec3& v) {
  return "[" + config::number(v.x) + ", " + config::number(v.y) + ", " + config::number(v.z) + "]";
}

// push-only stop on one axis: back inside [lo, hi], damping never pulls outwards
double stop_axis(double x, double v, double lo, double hi, double k, double c) {
  if (x > hi) return -std::max(0.0, k * (x - hi) + c * v);
  if (x < lo) return std::max(0.0, k * (lo - x) - c * v);
  return 0.0;
}

// nearest multiple of the resolution (none when 0)
double quantised(double x, double resolution) {
  return resolution > 0.0 ? std::round(x / resolution) * resolution : x;
}

}  // namespace

SimulatedForceDevice::SimulatedForceDevice(SimulatedForceParams params) : params_(std::move(params)) {}

void SimulatedForceDevice::configure() {
  configured_ = active_ = false;
  const SimulatedForceParams& p = params_;
  // the profile
  const auto found = devices::find_device_profile(p.profile);
  if (!found) {
    const std::string names = joined(devices::device_profile_names());
    refuse(kSimulatedForce, "unknown profile '" + p.profile + "' (profiles: " + names + ")", "set profile to one of: " + names);
  }
  profile_ = *found;
  if (!(profile_.moving_mass_kg > 0.0)) refuse(kSimulatedForce, "profile '" + p.profile + "' has no moving mass", "give the profile a moving_mass_kg > 0");
  // the params
  check_positive("hand_stiffness_n_per_m", p.hand_stiffness_n_per_m, true);
  check_positive("hand_damping_n_s_per_m", p.hand_damping_n_s_per_m, true);
  check_positive("stop_stiffness_n_per_m", p.stop_stiffness_n_per_m, false);
  check_positive("substep_s", p.substep_s, false);
  if (!math::finite(p.start_m) || !inside(p.start_m, profile_.workspace_min_m, profile_.workspace_max_m)) {
    refuse(kSimulatedForce, "start_m " + text(p.start_m) + " is outside the " + p.profile + " workspace",
           "set start_m inside " + text(profile_.workspace_min_m) + " .. " + text(profile_.workspace_max_m));
  }
  // the substep: accurate for the stiffest spring and for all damping together
  const double m = profile_.moving_mass_kg;
  stop_damping_n_s_per_m_ = 2.0 * std::sqrt(p.stop_stiffness_n_per_m * m);
  const double omega = std::sqrt((p.stop_stiffness_n_per_m + p.hand_stiffness_n_per_m) / m);
  const double damping = stop_damping_n_s_per_m_ + p.hand_damping_n_s_per_m + profile_.damping_n_s_per_m;
  max_substep_s_ = std::min(kMaxOmegaDt / omega, kMaxDampingDt * m / damping);
  if (p.substep_s > max_substep_s_ || p.substep_s < 1e-9) {
    refuse(kSimulatedForce, "substep_s " + config::number(p.substep_s) + " is too long for the stop and hand stiffness and damping",
           "set substep_s from 1e-9 to " + config::number(max_substep_s_) + " s, or soften the stop or the hand");
  }
  substep_ns_ = std::max<std::int64_t>(1, std::llround(p.substep_s * 1e9));
  // the hand: a path or a virtual subject (throws config::Error with file:line)
  if (!p.hand_path.empty() && !p.subject.empty()) refuse(kSimulatedForce, "both hand_path and subject are given", "give hand_path (a scripted hand) or subject (a virtual subject), not both");
  if (p.subject.empty()) hand_ = std::make_unique<ScriptedHand>(p.hand_path.empty() ? task::Trajectory{} : task::load_trajectory(p.hand_path));
  else hand_ = std::make_unique<VirtualSubject>(load_subject(p.subject), p.subject_seed, p.noise_seed);
  x_m_ = p.start_m;
  reset_hand();
  speed_clamps_ = 0;
  configured_ = true;
}

void SimulatedForceDevice::activate() {
  if (!configured_) refuse(kSimulatedForce, "activate before configure", "call configure() first");
  x_m_ = params_.start_m;
  command_faults_ = 0;
  started_ = false;
  reset_hand();
  active_ = true;
}

void SimulatedForceDevice::deactivate() noexcept {
  force_n_ = {};
  command_faults_ = 0;
  active_ = false;
}

bool SimulatedForceDevice::read(std::int64_t now_ns, ForceSample& out) noexcept {
  out.time_ns = now_ns;
  out.buttons = 0;
  // not active: nothing to read
  if (!active_) {
    out.faults = bit(DeviceFault::device_error);
    return false;
  }
  advance(now_ns);
  // the sensors: position quantised to the resolution, the true velocity
  out.time_ns = now_ns_;
  out.position_m = {quantised(x_m_.x, profile_.resolution_m), quantised(x_m_.y, profile_.resolution_m),
                    quantised(x_m_.z, profile_.resolution_m)};
  out.velocity_m_per_s = v_m_per_s_;
  out.faults = command_faults_ | (outside_workspace() ? bit(DeviceFault::workspace_limit) : 0u);
  return true;
}

void SimulatedForceDevice::write(std::int64_t now_ns, const Vec3& force_n) noexcept {
  if (!active_) return;
  advance(now_ns);
  // the amplifier: NaN/Inf gives no force, the magnitude saturates at the peak force
  command_faults_ = 0;
  force_n_ = force_n;
  if (!math::finite(force_n)) {
    force_n_ = {};
    command_faults_ = bit(DeviceFault::nonfinite_command);
    return;
  }
  const double magnitude = math::norm(force_n);
  if (magnitude > profile_.peak_force_n) {
    force_n_ = force_n * (profile_.peak_force_n / magnitude);
    command_faults_ = bit(DeviceFault::clamped);
  }
}

void SimulatedForceDevice::start_clock(std::int64_t now_ns) noexcept {
  started_ = true;
  start_ns_ = now_ns_ = now_ns;
}

void SimulatedForceDevice::advance(std::int64_t now_ns) noexcept {
  if (!started_) start_clock(now_ns);
  // substeps of substep_ns_, the last one shorter
  while (now_ns_ < now_ns) substep(std::min(now_ns, now_ns_ + substep_ns_));
}

void SimulatedForceDevice::substep(std::int64_t to_ns) noexcept {
  const double dt = static_cast<double>(to_ns - now_ns_) * 1e-9;
  const double m = profile_.moving_mass_kg;
  // the hand: spring towards the target, damper on the velocity relative to the target's;
  // the target comes from the hand source, given what the hand feels now
  const Vec3 hand_next = hand_->target(to_ns - start_ns_, {x_m_, v_m_per_s_, -hand_force_n_});
  const Vec3 hand_velocity = (hand_next - hand_m_) * (1.0 / dt);
  hand_force_n_ = (hand_m_ - x_m_) * params_.hand_stiffness_n_per_m + (hand_velocity - v_m_per_s_) * params_.hand_damping_n_s_per_m;
  // all forces at the start of the substep; velocity first, then position (semi-implicit)
  const Vec3 force = force_n_ + hand_force_n_ - v_m_per_s_ * profile_.damping_n_s_per_m + stop_force_n();
  v_m_per_s_ += force * (dt / m);
  // the speed limit
  const double speed = math::norm(v_m_per_s_);
  if (speed > profile_.max_speed_m_per_s) {
    v_m_per_s_ *= profile_.max_speed_m_per_s / speed;
    ++speed_clamps_;
  }
  x_m_ += v_m_per_s_ * dt;
  hand_m_ = hand_next;
  now_ns_ = to_ns;
}

// the handle at rest at the start, the hand's trial at time 0
void SimulatedForceDevice::reset_hand() noexcept {
  v_m_per_s_ = force_n_ = hand_force_n_ = {};
  hand_->reset({params_.start_m, params_.hand_stiffness_n_per_m});
  hand_m_ = hand_->target(0, {x_m_, {}, {}});
}

Vec3 SimulatedForceDevice::stop_force_n() const noexcept {
  const Vec3& lo = profile_.workspace_min_m;
  const Vec3& hi = profile_.workspace_max_m;
  const double k = params_.stop_stiffness_n_per_m;
  const double c = stop_damping_n_s_per_m_;
  return {stop_axis(x_m_.x, v_m_per_s_.x, lo.x, hi.x, k, c), stop_axis(x_m_.y, v_m_per_s_.y, lo.y, hi.y, k, c),
          stop_axis(x_m_.z, v_m_per_s_.z, lo.z, hi.z, k, c)};
}

bool SimulatedForceDevice::outside_workspace() const noexcept {
  return !inside(x_m_, profile_.workspace_min_m, profile_.workspace_max_m);
}

}  // namespace enact::devices
