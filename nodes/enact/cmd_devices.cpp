// enact devices: the supported USB devices on this machine's bus.
#include <cstdio>

#include "core/devices/usb/libusb.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kHelp = R"(usage: enact devices [--udev-rules]

List the supported USB devices on this machine's bus: a Novint Falcon (device: falcon) and
Metec Braille cells (device: metec), with their USB id, device file, serial, and whether
enact may open them. When one may not (permission denied), prints the udev rules that give
the logged-in user access, and how to install them (scripts/udev/99-enact.rules).
Exit 0 when a supported device was found, 1 when none was.

options:
  --udev-rules   print the udev rules only (e.g. | sudo tee /etc/udev/rules.d/99-enact.rules)
)";

}  // namespace

int devices(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {}, {"udev-rules"});
  if (a.flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (!a.positional.empty()) throw UsageError("unexpected argument '" + a.positional.front() + "'");
  if (a.flag("udev-rules")) {
    std::fputs(devices::usb::udev_rules().c_str(), stdout);
    return 0;
  }
  devices::usb::LibusbBus bus;
  const auto found = bus.list();
  std::fputs(devices::usb::report(found).c_str(), stdout);
  return found.empty() ? 1 : 0;
}

}  // namespace enact::cli
