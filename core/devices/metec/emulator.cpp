#include "core/devices/metec/emulator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/rt/clock.h"

namespace enact::devices::metec {

MetecEmulator::MetecEmulator(MetecEmulatorParams params) : params_(std::move(params)) {
  const int c = params_.cells;
  if (c < kCellsPerModule || c > kMaxModules * kCellsPerModule || c % kCellsPerModule != 0) {
    throw std::invalid_argument("Metec emulator: cells must be a multiple of 8 from 8 to 80");
  }
  if (!(params_.rise_time_s > 0.0) || !std::isfinite(params_.rise_time_s)) throw std::invalid_argument("Metec emulator: rise_time_s must be > 0");
  latched_.assign(static_cast<std::size_t>(c), 0);
  PinMotion still;
  still.rise_ns = params_.rise_time_s * 1e9;
  dots_.assign(static_cast<std::size_t>(c), still);
  module_writes_.assign(static_cast<std::size_t>(c / kCellsPerModule), 0);
}

std::int64_t MetecEmulator::now() const { return params_.clock ? params_.clock() : rt::now_ns(); }

// a cell's dots head for its latched byte while the high voltage is on, else down
void MetecEmulator::show_locked(int cell, std::int64_t now_ns) {
  const auto i = static_cast<std::size_t>(cell);
  std::uint32_t targets = 0;
  for (int dot = 1; dot <= 8; ++dot) {
    if (high_voltage_ && (latched_[i] & dot_bit(dot))) targets |= 1u << (dot - 1);
  }
  dots_[i].set_targets(now_ns, targets, 8);
}

usb::Outcome MetecEmulator::control(const usb::ControlSetup& s, std::uint8_t* data, std::uint16_t length) {
  std::lock_guard lock(mutex_);
  const std::int64_t t = now();
  const int cells = static_cast<int>(latched_.size());
  // the status, device to host
  if (s.request_type == usb::kVendorIn && s.request == kGetStatus) {
    const auto status = encode_status({kNoRoutingKey, cells, 0});
    const int n = std::min<int>(length, kStatusSize);
    std::copy_n(status.begin(), n, data);
    return {usb::Status::ok, n};
  }
  if (s.request_type != usb::kVendorOut) return {usb::Status::stall, 0};
  // high voltage on / off
  if (s.request == kSetHighVoltage && length == 1 && (data[0] == kHighVoltageOn || data[0] == kHighVoltageOff)) {
    const bool on = data[0] == kHighVoltageOn;
    hv_switches_ += on != high_voltage_;
    high_voltage_ = on;
    for (int c = 0; c < cells; ++c) show_locked(c, t);
    return {usb::Status::ok, 1};
  }
  // the identity, answered on the input endpoint
  if (s.request == kIdentify && length == 1) {
    pending_identity_ = params_.identity;
    return {usb::Status::ok, 1};
  }
  // a module's 8 cells
  const int module = s.request - kWriteModule;
  if (module >= 0 && module < cells / kCellsPerModule && length == kCellsPerModule) {
    for (int k = 0; k < kCellsPerModule; ++k) {
      latched_[static_cast<std::size_t>(module * kCellsPerModule + k)] = data[k];
      show_locked(module * kCellsPerModule + k, t);
    }
    ++module_writes_[static_cast<std::size_t>(module)];
    return {usb::Status::ok, length};
  }
  return {usb::Status::stall, 0};
}

usb::Outcome MetecEmulator::out(std::uint8_t, const std::uint8_t*, int) { return {usb::Status::stall, 0}; }

usb::Outcome MetecEmulator::in(std::uint8_t endpoint, std::uint8_t* data, int length) {
  if (endpoint != kEndpointIn) return {usb::Status::stall, 0};
  std::lock_guard lock(mutex_);
  if (pending_identity_.empty()) return {usb::Status::timeout, 0};
  const int n = std::min<int>(length, static_cast<int>(pending_identity_.size()));
  std::copy_n(pending_identity_.begin(), n, data);
  pending_identity_.clear();
  return {usb::Status::ok, n};
}

bool MetecEmulator::high_voltage() const {
  std::lock_guard lock(mutex_);
  return high_voltage_;
}

std::uint8_t MetecEmulator::cell(int index) const {
  std::lock_guard lock(mutex_);
  return latched_.at(static_cast<std::size_t>(index));
}

double MetecEmulator::dot_level(int cell, int dot, std::int64_t now_ns) const {
  std::lock_guard lock(mutex_);
  return dots_.at(static_cast<std::size_t>(cell)).level(dot - 1, now_ns);
}

std::uint64_t MetecEmulator::module_writes(int module) const {
  std::lock_guard lock(mutex_);
  return module_writes_.at(static_cast<std::size_t>(module));
}

std::uint64_t MetecEmulator::high_voltage_switches() const {
  std::lock_guard lock(mutex_);
  return hv_switches_;
}

}  // namespace enact::devices::metec
