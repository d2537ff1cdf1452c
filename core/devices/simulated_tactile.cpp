#include "core/devices/simulated_tactile.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/config/format.h"
#include "core/devices/params_error.h"

namespace enact::devices {
namespace {

constexpr const char* kSimulatedTactile = "simulated tactile device";
constexpr int kMaxPins = 32;

}  // namespace

SimulatedTactileDevice::SimulatedTactileDevice(SimulatedTactileParams params) : params_(params) {}

void SimulatedTactileDevice::configure() {
  configured_ = active_ = false;
  const SimulatedTactileParams& p = params_;
  // the pin grid fits a 32-bit pin word
  if (p.rows < 1 || p.cols < 1 || p.rows > kMaxPins || p.cols > kMaxPins || p.rows * p.cols > kMaxPins) {
    refuse(kSimulatedTactile, std::to_string(p.rows) + " x " + std::to_string(p.cols) + " pins is not 1 to 32 pins",
           "set rows and cols >= 1 with rows * cols <= 32");
  }
  if (!std::isfinite(p.rise_time_s) || p.rise_time_s <= 0.0) {
    refuse(kSimulatedTactile, "rise_time_s is " + config::number(p.rise_time_s), "set rise_time_s to the cells' full-stroke time (> 0 s; Metec: 0.024)");
  }
  const int count = p.rows * p.cols;
  mask_ = count == kMaxPins ? ~0u : (1u << count) - 1u;
  // every pin down, at rest
  motion_ = {};
  motion_.rise_ns = p.rise_time_s * 1e9;
  seen_ = false;
  configured_ = true;
}

void SimulatedTactileDevice::activate() {
  if (!configured_) refuse(kSimulatedTactile, "activate before configure", "call configure() first");
  active_ = true;
}

void SimulatedTactileDevice::write(std::int64_t now_ns, std::uint32_t pins) noexcept {
  if (!active_) return;
  see(now_ns);
  motion_.set_targets(now_ns, pins & mask_, params_.rows * params_.cols);
}

void SimulatedTactileDevice::shown(std::int64_t now_ns, float* levels, int count) noexcept {
  see(now_ns);
  const int n = std::min(count, params_.rows * params_.cols);
  for (int i = 0; i < n; ++i) levels[i] = static_cast<float>(level(i, now_ns));
}

bool SimulatedTactileDevice::motion(PinMotion& out) const noexcept {
  out = motion_;
  return true;
}

void SimulatedTactileDevice::deactivate() noexcept {
  if (configured_) motion_.set_targets(latest_ns_, 0, params_.rows * params_.cols);
  active_ = false;
}

void SimulatedTactileDevice::see(std::int64_t now_ns) noexcept {
  latest_ns_ = seen_ ? std::max(latest_ns_, now_ns) : now_ns;
  seen_ = true;
}

}  // namespace enact::devices
