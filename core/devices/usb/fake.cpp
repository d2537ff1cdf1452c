#include "core/devices/usb/fake.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>

namespace enact::devices::usb {

Emulator::~Emulator() = default;

FakeTransport::FakeTransport(std::shared_ptr<Emulator> emulator, std::shared_ptr<FakeCable> cable)
    : emulator_(std::move(emulator)), cable_(std::move(cable)) {}

bool FakeTransport::blocked(int timeout_ms, Outcome& out) noexcept {
  cable_->transfers.fetch_add(1, std::memory_order_relaxed);
  if (cable_->unplugged.load()) {
    out = {Status::no_device, 0};
    return true;
  }
  if (cable_->stalled.load()) {
    // a device that does not answer: the transfer waits its timeout, like libusb's
    std::this_thread::sleep_for(std::chrono::milliseconds(std::max(timeout_ms, 0)));
    out = {Status::timeout, 0};
    return true;
  }
  return false;
}

Outcome FakeTransport::control(const ControlSetup& setup, std::uint8_t* data, std::uint16_t length, int timeout_ms) noexcept {
  Outcome out;
  if (blocked(timeout_ms, out)) return out;
  try {
    return emulator_->control(setup, data, length);
  } catch (...) {
    return {Status::io, 0};
  }
}

Outcome FakeTransport::transfer(std::uint8_t endpoint, std::uint8_t* data, int length, int timeout_ms) noexcept {
  Outcome out;
  if (blocked(timeout_ms, out)) return out;
  try {
    return (endpoint & 0x80) ? emulator_->in(endpoint, data, length) : emulator_->out(endpoint, data, length);
  } catch (...) {
    return {Status::io, 0};
  }
}

Outcome FakeTransport::bulk(std::uint8_t endpoint, std::uint8_t* data, int length, int timeout_ms) noexcept {
  return transfer(endpoint, data, length, timeout_ms);
}

Outcome FakeTransport::interrupt(std::uint8_t endpoint, std::uint8_t* data, int length, int timeout_ms) noexcept {
  return transfer(endpoint, data, length, timeout_ms);
}

// async-signal-safe: atomics, a fixed buffer and write(2)
bool FakeTransport::record(int request, const std::uint8_t* data, int length) noexcept {
  if (cable_->unplugged.load()) return false;
  const int n = std::min<int>(length, static_cast<int>(cable_->emergency_bytes.size()));
  for (int i = 0; i < n; ++i) cable_->emergency_bytes[static_cast<std::size_t>(i)] = data[i];
  cable_->emergency_length.store(n);
  cable_->emergency_request.store(request);
  cable_->emergencies.fetch_add(1);
  if (const int fd = cable_->emergency_fd.load(); fd >= 0) {
    std::uint8_t head[2] = {static_cast<std::uint8_t>(request < 0 ? 0xFF : request), static_cast<std::uint8_t>(n)};
    if (::write(fd, head, 2) != 2 || ::write(fd, data, static_cast<std::size_t>(n)) != n) return false;
  }
  return true;
}

bool FakeTransport::emergency_control_out(const ControlSetup& setup, const std::uint8_t* data, std::uint16_t length) noexcept {
  return record(setup.request, data, length);
}

bool FakeTransport::emergency_bulk_out(std::uint8_t, const std::uint8_t* data, int length) noexcept { return record(-1, data, length); }

std::vector<Found> FakeBus::list() {
  std::vector<Found> out;
  for (const auto& d : devices_) out.push_back(d.found);
  return out;
}

Opened FakeBus::open(const Found& device, const Claim& claim) {
  Opened out;
  for (const auto& d : devices_) {
    if (d.found.path != device.path) continue;
    claims_.push_back(claim);
    out.status = d.cable->unplugged.load() ? Status::no_device : d.open_status;
    if (out.status == Status::ok) out.transport = std::make_unique<FakeTransport>(d.emulator, d.cable);
    if (out.status == Status::access) out.detail = "open " + d.found.path + ": Permission denied";
    return out;
  }
  out.status = Status::not_found;
  return out;
}

FakeDevice emulated_device(const std::string& backend, std::shared_ptr<Emulator> emulator) {
  const SupportedDevice& kind = supported(backend);
  FakeDevice d;
  d.found.vendor = kind.vendor;
  d.found.product = kind.product;
  d.found.bus = 1;
  d.found.address = 1;
  d.found.path = "emulator:" + backend;
  d.found.serial = "EMULATED";
  d.emulator = std::move(emulator);
  return d;
}

}  // namespace enact::devices::usb
