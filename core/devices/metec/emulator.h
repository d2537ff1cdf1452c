#pragma once
// An emulated Metec Braille display at the packet level, for a fake USB transport
// (usb/fake.h): high voltage on/off, the identity request (the text comes on the input
// endpoint), the 8-byte status, and module writes of 8 cells. Each dot moves like the
// cells do (PinMotion: a full stroke in rise_time_s, 24 ms for Metec cells), from the time
// its write arrives; with the high voltage off every dot drops. A test reads what each dot
// physically shows at any time, what each cell latched, and how many times each module was
// written. Modelled from BRLTTY's description, not measured on a display.
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "core/devices/device.h"
#include "core/devices/metec/protocol.h"
#include "core/devices/usb/fake.h"
#include "core/rt/clock.h"

namespace enact::devices::metec {

struct MetecEmulatorParams {
  int cells = 16;                 // 8 .. 80, a multiple of 8 (whole modules)
  double rise_time_s = 0.024;     // > 0
  std::string identity = "enact Metec emulator";
  rt::ClockFn clock = nullptr;  // monotonic ns; null: CLOCK_MONOTONIC
};

class MetecEmulator final : public usb::Emulator {
 public:
  // throws std::invalid_argument on bad params
  explicit MetecEmulator(MetecEmulatorParams params = {});

  usb::Outcome control(const usb::ControlSetup& setup, std::uint8_t* data, std::uint16_t length) override;
  usb::Outcome out(std::uint8_t endpoint, const std::uint8_t* data, int length) override;
  usb::Outcome in(std::uint8_t endpoint, std::uint8_t* data, int length) override;

  // what a test reads (each call locks)
  bool high_voltage() const;
  std::uint8_t cell(int index) const;                         // the latched byte
  double dot_level(int cell, int dot, std::int64_t now_ns) const;  // 0 down .. 1 up, physically
  std::uint64_t module_writes(int module) const;
  std::uint64_t high_voltage_switches() const;

 private:
  void show_locked(int cell, std::int64_t now_ns);
  std::int64_t now() const;

  mutable std::mutex mutex_;
  MetecEmulatorParams params_;
  bool high_voltage_ = false;
  std::vector<std::uint8_t> latched_;
  std::vector<PinMotion> dots_;  // one per cell, pin i = dot i + 1
  std::vector<std::uint64_t> module_writes_;
  std::uint64_t hv_switches_ = 0;
  std::string pending_identity_;  // waiting on the input endpoint
};

}  // namespace enact::devices::metec
