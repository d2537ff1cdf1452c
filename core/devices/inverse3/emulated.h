#pragma once
// An Inverse3 backend talking to its own emulated service (`transport: emulator`): the
// emulator (emulator.h) on free loopback ports, and the backend (inverse3_device.h)
// connected to them, as one ForceDevice that owns both (the backend goes first).
#include <memory>

#include "core/devices/inverse3/emulator.h"
#include "core/devices/inverse3/inverse3_device.h"

namespace enact::devices::inverse3 {

class EmulatedInverse3 final : public ForceDevice {
 public:
  // the emulator starts now (on free ports: the ports in `device` are replaced by them)
  EmulatedInverse3(Inverse3Params device, Inverse3EmulatorParams emulator);

  void configure() override { device_->configure(); }
  void activate() override { device_->activate(); }
  bool read(std::int64_t now_ns, ForceSample& out) noexcept override { return device_->read(now_ns, out); }
  void write(std::int64_t now_ns, const math::Vec3& force_n) noexcept override { device_->write(now_ns, force_n); }
  void deactivate() noexcept override { device_->deactivate(); }
  const devices::DeviceProfile& profile() const override { return device_->profile(); }

  Inverse3Emulator& emulator() { return *emulator_; }
  Inverse3ForceDevice& device() { return *device_; }

 private:
  std::unique_ptr<Inverse3Emulator> emulator_;
  std::unique_ptr<Inverse3ForceDevice> device_;
};

}  // namespace enact::devices::inverse3
