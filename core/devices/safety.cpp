#include "core/devices/safety.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "core/config/format.h"
#include "core/devices/params_error.h"

namespace enact::devices {
namespace {

constexpr const char* kSafety = "force device safety";

// the slew limit's interval: a longer silence allows no larger step than this
constexpr std::int64_t kStepInterval_ns = 1'000'000;

}  // namespace

SafeForceDevice::SafeForceDevice(std::unique_ptr<ForceDevice> inner, SafetyParams params)
    : inner_(std::move(inner)), params_(params) {
  if (!inner_) throw std::invalid_argument("SafeForceDevice: no inner device");
}

void SafeForceDevice::configure() {
  // the params, then the inner device
  if (!std::isfinite(params_.watchdog_s) || params_.watchdog_s <= 0.0) {
    refuse(kSafety, "watchdog_s is " + config::number(params_.watchdog_s), "set watchdog_s to a few loop periods (> 0 s; default 0.010)");
  }
  if (!std::isfinite(params_.ramp_s) || params_.ramp_s < 0.0) {
    refuse(kSafety, "ramp_s is " + config::number(params_.ramp_s), "set ramp_s >= 0 s (default 0.005; 0: cut at once)");
  }
  if (!std::isfinite(params_.reengage_s) || params_.reengage_s < 0.0) {
    refuse(kSafety, "reengage_s is " + config::number(params_.reengage_s), "set reengage_s >= 0 s (default 0.100; 0: no ramp back)");
  }
  watchdog_ns_ = std::llround(params_.watchdog_s * 1e9);
  ramp_ns_ = std::llround(params_.ramp_s * 1e9);
  reengage_ns_ = std::llround(params_.reengage_s * 1e9);
  inner_->configure();
  if (!(profile().peak_force_n > 0.0)) {
    refuse(kSafety, "the device profile '" + profile().name + "' has no peak force", "give the profile a peak_force_n > 0");
  }
  if (!(profile().max_force_step_n_per_ms > 0.0)) {
    refuse(kSafety, "the device profile '" + profile().name + "' has no force step limit",
           "give the profile a max_force_step_n_per_ms > 0");
  }
  step_n_per_ns_ = profile().max_force_step_n_per_ms / static_cast<double>(kStepInterval_ns);
}

void SafeForceDevice::activate() {
  inner_->activate();
  command_n_ = sent_n_ = trip_n_ = {};
  command_faults_ = faults_ = 0;
  commanded_ = in_episode_ = seen_ = sent_any_ = false;
  interrupted_ = true;
}

void SafeForceDevice::write(std::int64_t now_ns, const math::Vec3& force_n) noexcept {
  see(now_ns);
  // a fresh command: finite, within the peak force
  command_n_ = force_n;
  command_faults_ = 0;
  const double peak = profile().peak_force_n;
  if (!math::finite(force_n)) {
    command_n_ = {};
    command_faults_ = bit(DeviceFault::nonfinite_command);
    ++nonfinite_;
  } else if (const double magnitude = math::norm(force_n); magnitude > peak) {
    command_n_ = force_n * (peak / magnitude);
    command_faults_ = bit(DeviceFault::clamped);
    ++clamps_;
  }
  commanded_ = true;
  command_ns_ = now_ns;
  in_episode_ = false;
  faults_ = (faults_ & ~(bit(DeviceFault::watchdog) | bit(DeviceFault::clamped) | bit(DeviceFault::nonfinite_command))) | command_faults_;
  send(now_ns, command_n_ * engagement(now_ns));
}

double SafeForceDevice::engagement(std::int64_t now_ns) noexcept {
  // the first write after an interruption begins a ramp from zero
  if (interrupted_) {
    interrupted_ = false;
    engage_ns_ = now_ns;
    ++reengagements_;
  }
  const std::int64_t since_ns = now_ns - engage_ns_;
  if (since_ns >= reengage_ns_) return 1.0;
  return since_ns <= 0 ? 0.0 : static_cast<double>(since_ns) / static_cast<double>(reengage_ns_);
}

bool SafeForceDevice::read(std::int64_t now_ns, ForceSample& out) noexcept {
  see(now_ns);
  const bool ok = inner_->read(now_ns, out);
  // the watchdog: past watchdog_ns_ without a command, ramp the last command to zero
  const std::int64_t late_ns = now_ns - command_ns_ - watchdog_ns_;
  if (commanded_ && late_ns > 0) {
    if (!in_episode_) {
      ++watchdog_trips_;
      trip_n_ = sent_n_;
    }
    in_episode_ = interrupted_ = true;
    const double left = late_ns >= ramp_ns_ ? 0.0 : 1.0 - static_cast<double>(late_ns) / static_cast<double>(ramp_ns_);
    send(now_ns, trip_n_ * left);
  }
  // a device that failed to read: the force goes to zero (at the slew limit) while it fails,
  // and comes back gently after
  if (!ok) {
    interrupted_ = true;
    send(now_ns, {});
  }
  out.faults |= command_faults_ | (in_episode_ ? bit(DeviceFault::watchdog) : 0u) | (ok ? 0u : bit(DeviceFault::device_error));
  out.force_n = sent_n_;
  faults_ = out.faults;
  return ok;
}

void SafeForceDevice::deactivate() noexcept {
  // zero at once: the device is being switched off
  sent_n_ = {};
  inner_->write(latest_ns_, sent_n_);
  inner_->deactivate();
  in_episode_ = commanded_ = false;
}

void SafeForceDevice::send(std::int64_t now_ns, const math::Vec3& force_n) noexcept {
  sent_n_ = slew_limit(now_ns, force_n);
  sent_ns_ = now_ns;
  sent_any_ = true;
  inner_->write(now_ns, sent_n_);
}

math::Vec3 SafeForceDevice::slew_limit(std::int64_t now_ns, const math::Vec3& force_n) noexcept {
  // the step allowed since the last force sent (a first one: a whole interval's)
  const std::int64_t dt_ns = sent_any_ ? std::clamp<std::int64_t>(now_ns - sent_ns_, 0, kStepInterval_ns) : kStepInterval_ns;
  const double allowed_n = step_n_per_ns_ * static_cast<double>(dt_ns);
  const math::Vec3 step = force_n - sent_n_;
  const double size = math::norm(step);
  if (size <= allowed_n) return force_n;
  ++slew_limited_;
  return sent_n_ + step * (allowed_n / size);
}

void SafeForceDevice::see(std::int64_t now_ns) noexcept {
  latest_ns_ = seen_ ? std::max(latest_ns_, now_ns) : now_ns;
  seen_ = true;
}

}  // namespace enact::devices
