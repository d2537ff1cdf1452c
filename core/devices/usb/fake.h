#pragma once
// A fake USB bus and transport that play a device emulator at the packet level: the backend
// above sends and receives the very bytes it would exchange with the hardware, and the
// emulator implements the device's side of the protocol. The cable between them can be
// unplugged (every transfer then answers no_device) or made to stall (the device stops
// answering: transfers time out), and records the emergency transfers a fatal-signal
// handler makes (async-signal-safe: a fixed buffer, and optionally a write(2) to a file).
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/devices/usb/transport.h"

namespace enact::devices::usb {

// the device side of a fake transport; called by one thread at a time (a backend's
// configure, then its I/O thread); each implementation guards with a lock the state its
// test accessors read from other threads
class Emulator {
 public:
  virtual ~Emulator();
  // a control transfer: fill `data` (device to host) or take it (host to device)
  virtual Outcome control(const ControlSetup& setup, std::uint8_t* data, std::uint16_t length) = 0;
  // host to device on `endpoint` (bulk or interrupt)
  virtual Outcome out(std::uint8_t endpoint, const std::uint8_t* data, int length) = 0;
  // device to host on `endpoint` (bulk or interrupt): what the device has, or a timeout
  virtual Outcome in(std::uint8_t endpoint, std::uint8_t* data, int length) = 0;
};

// the cable: what a test does to the connection, and what went through it in emergencies
struct FakeCable {
  std::atomic<bool> unplugged{false};  // every transfer answers no_device
  std::atomic<bool> stalled{false};    // every transfer times out (after sleeping its timeout)
  std::atomic<std::uint64_t> transfers{0};  // transfers attempted
  // emergency transfers: the last one's bytes, and how many were made
  std::atomic<int> emergencies{0};
  std::array<std::uint8_t, 64> emergency_bytes{};
  std::atomic<int> emergency_length{0};
  std::atomic<int> emergency_request{-1};  // the control request, or -1 for a bulk transfer
  // when >= 0, each emergency transfer is also written there: [request or 0xFF, length, bytes...]
  std::atomic<int> emergency_fd{-1};
};

class FakeTransport final : public Transport {
 public:
  FakeTransport(std::shared_ptr<Emulator> emulator, std::shared_ptr<FakeCable> cable);

  Outcome control(const ControlSetup& setup, std::uint8_t* data, std::uint16_t length, int timeout_ms) noexcept override;
  Outcome bulk(std::uint8_t endpoint, std::uint8_t* data, int length, int timeout_ms) noexcept override;
  Outcome interrupt(std::uint8_t endpoint, std::uint8_t* data, int length, int timeout_ms) noexcept override;
  bool emergency_control_out(const ControlSetup& setup, const std::uint8_t* data, std::uint16_t length) noexcept override;
  bool emergency_bulk_out(std::uint8_t endpoint, const std::uint8_t* data, int length) noexcept override;

 private:
  // true (with the outcome) when the cable is unplugged or stalled
  bool blocked(int timeout_ms, Outcome& out) noexcept;
  Outcome transfer(std::uint8_t endpoint, std::uint8_t* data, int length, int timeout_ms) noexcept;
  bool record(int request, const std::uint8_t* data, int length) noexcept;

  std::shared_ptr<Emulator> emulator_;
  std::shared_ptr<FakeCable> cable_;
};

// a device on the fake bus
struct FakeDevice {
  Found found;                          // what list() shows
  std::shared_ptr<Emulator> emulator;   // what open() connects to
  std::shared_ptr<FakeCable> cable = std::make_shared<FakeCable>();
  Status open_status = Status::ok;      // what open() answers (access: permission denied, ...)
};

class FakeBus final : public Bus {
 public:
  FakeBus() = default;
  explicit FakeBus(std::vector<FakeDevice> devices) : devices_(std::move(devices)) {}
  void add(FakeDevice device) { devices_.push_back(std::move(device)); }

  std::vector<Found> list() override;
  Opened open(const Found& device, const Claim& claim) override;
  // the claims made by open(), in order
  const std::vector<Claim>& claims() const { return claims_; }

 private:
  std::vector<FakeDevice> devices_;
  std::vector<Claim> claims_;
};

// a fake bus with one emulated device of `backend` (serial "EMULATED"), and its cable
FakeDevice emulated_device(const std::string& backend, std::shared_ptr<Emulator> emulator);

}  // namespace enact::devices::usb
