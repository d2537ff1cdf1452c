#pragma once
// Helpers of the USB backend tests: a fake bus holding one emulated device (the test keeps
// the emulator and the cable), polling for a condition with a bound (no timing assertion:
// the bound only keeps a broken program from hanging the suite), the message of a refusal,
// and a recording emulator.
#include <chrono>
#include <functional>
#include <memory>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/config/yaml.h"
#include "core/devices/usb/fake.h"
#include "tests/support/refusal.h"

namespace enact::test {

// a fake bus with one emulated device of `backend`; the cable stays reachable
template <class Emu>
struct OnBus {
  std::shared_ptr<Emu> emulator;
  std::shared_ptr<devices::usb::FakeCable> cable;
  std::unique_ptr<devices::usb::FakeBus> bus;
  OnBus(const std::string& backend, std::shared_ptr<Emu> emu, devices::usb::Status open_status = devices::usb::Status::ok) : emulator(std::move(emu)) {
    devices::usb::FakeDevice d = devices::usb::emulated_device(backend, emulator);
    d.open_status = open_status;
    cable = d.cable;
    bus = std::make_unique<devices::usb::FakeBus>();
    bus->add(std::move(d));
  }
};

// forwards to an emulator, logging the control requests and the bytes sent to it
class Recording final : public devices::usb::Emulator {
 public:
  explicit Recording(std::shared_ptr<devices::usb::Emulator> inner) : inner_(std::move(inner)) {}
  devices::usb::Outcome control(const devices::usb::ControlSetup& s, std::uint8_t* data, std::uint16_t length) override {
    controls.push_back(s);
    return inner_->control(s, data, length);
  }
  devices::usb::Outcome out(std::uint8_t endpoint, const std::uint8_t* data, int length) override {
    sent.emplace_back(data, data + length);
    return inner_->out(endpoint, data, length);
  }
  devices::usb::Outcome in(std::uint8_t endpoint, std::uint8_t* data, int length) override {
    devices::usb::Outcome o = inner_->in(endpoint, data, length);
    // a corrupted line: the last byte of what came in is flipped
    if (corrupt_in && o.bytes > 2) data[o.bytes - 1] ^= 0x01;
    return o;
  }

  std::vector<devices::usb::ControlSetup> controls;
  std::vector<std::vector<std::uint8_t>> sent;
  bool corrupt_in = false;

 private:
  std::shared_ptr<devices::usb::Emulator> inner_;
};

}  // namespace enact::test
