#include "core/devices/inverse3/emulated.h"

namespace enact::devices::inverse3 {

EmulatedInverse3::EmulatedInverse3(Inverse3Params device, Inverse3EmulatorParams emulator) {
  emulator.port = 0;
  emulator.events_port = 0;
  emulator_ = std::make_unique<Inverse3Emulator>(std::move(emulator));
  device.host = "127.0.0.1";
  device.port = emulator_->port();
  device.events_port = emulator_->events_port();
  device_ = std::make_unique<Inverse3ForceDevice>(std::move(device));
}

}  // namespace enact::devices::inverse3
