#pragma once
// A simulated tactile pin array: each pin moves as PinMotion says with a full stroke of
// rise_time_s (Metec cells: 24 ms), starting at the time of the write that changed its
// target. Allocates nothing after construction.
//
// Being a simulation, the pins keep moving while the device is inactive: deactivate() sets
// every target down at the latest time the device has seen (its last write or shown), and
// shown() then shows the pins falling from there.
#include <cstdint>

#include "core/devices/device.h"

namespace enact::devices {

struct SimulatedTactileParams {
  int rows = 4;               // >= 1, rows * cols <= 32
  int cols = 4;               // >= 1
  double rise_time_s = 0.024; // > 0, the time of a full stroke (Metec cells)
};

class SimulatedTactileDevice final : public TactileDevice {
 public:
  explicit SimulatedTactileDevice(SimulatedTactileParams params = {});

  // validate the params; every pin down; throws config::Error
  void configure() override;
  // enable writes (pins as they are: down after configure or deactivate)
  void activate() override;
  // the targets from now_ns on (bits beyond rows * cols ignored; ignored when not active)
  void write(std::int64_t now_ns, std::uint32_t pins) noexcept override;
  // the levels at now_ns, pins 0 .. min(count, rows * cols)
  void shown(std::int64_t now_ns, float* levels, int count) noexcept override;
  bool motion(PinMotion& out) const noexcept override;
  int rows() const override { return params_.rows; }
  int cols() const override { return params_.cols; }
  // every target down from the latest time seen, disable writes
  void deactivate() noexcept override;

  // the current targets (bit i = pin i up)
  std::uint32_t targets() const { return motion_.targets; }
  // one pin's level at now_ns, 0 .. 1 (not before the pin's last target change)
  double level(int pin, std::int64_t now_ns) const noexcept { return motion_.level(pin, now_ns); }

 private:
  void see(std::int64_t now_ns) noexcept;

  SimulatedTactileParams params_;
  PinMotion motion_;
  std::uint32_t mask_ = 0;     // the bits of existing pins
  std::int64_t latest_ns_ = 0; // the latest time seen
  bool seen_ = false;
  bool configured_ = false;
  bool active_ = false;
};

}  // namespace enact::devices
