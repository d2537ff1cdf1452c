// enact devices: the supported devices on this machine: USB devices on the bus, and the
// devices behind a vendor's SDK or service.
#include <cstdio>

#include "core/config/format.h"
#include "core/config/share.h"
#include "core/devices/device_profile.h"
#include "core/devices/inverse3/probe.h"
#include "core/devices/inverse3/protocol.h"
#include "core/devices/usb/libusb.h"
#include "core/devices/vendor/probe.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kDevicesHelp = R"(usage: enact devices [--udev-rules] [--profiles] [--dhd-library PATH] [--hd-library PATH]
                     [--hd-device NAME] [--inverse3-port N]

List the supported devices on this machine, and say what is missing for those absent:
- on the USB bus: a Novint Falcon (device: falcon) and Metec Braille cells (device: metec),
  with their USB id, device file, serial, and whether enact may open them. When one may not
  (permission denied), prints the udev rules that give the logged-in user access, and how to
  install them (the file: enact share scripts/udev/99-enact.rules);
- Force Dimension devices (device: dhd) through the Force Dimension SDK's libdhd, loaded now;
- OpenHaptics devices such as a 3D Systems Touch (device: hd) through libHD, loaded now;
- a Haply Inverse3 (device: inverse3) through the Haply Inverse Service on this machine.
Exit 0 when a supported device was found, 1 when none was.

options:
  --udev-rules        print the udev rules only (e.g. | sudo tee /etc/udev/rules.d/99-enact.rules)
  --profiles          print the device profiles (device: ... profile: NAME) with their limits
  --dhd-library PATH  the Force Dimension SDK's library (default libdhd.so, on the loader's path)
  --hd-library PATH   OpenHaptics' library (default libHD.so, on the loader's path)
  --hd-device NAME    the OpenHaptics device's name in Touch Setup (default: the default device)
  --inverse3-port N   the Inverse Service's simulation channel on 127.0.0.1 (default 10001)
)";

constexpr double kServiceTimeout_s = 1.0;

std::string profiles() {
  std::string out;
  for (const auto& name : devices::device_profile_names()) {
    const auto p = *devices::find_device_profile(name);
    const math::Vec3 size = p.workspace_max_m - p.workspace_min_m;
    char line[256];
    std::snprintf(line, sizeof line, "%-9s workspace %.0f x %.0f x %.0f mm  peak %s N  continuous %s N  force step %s N/ms  stiffness %s\n", name.c_str(),
                  size.x * 1e3, size.y * 1e3, size.z * 1e3, config::number(p.peak_force_n).c_str(), config::number(p.continuous_force_n).c_str(),
                  config::number(p.max_force_step_n_per_ms).c_str(),
                  p.max_stiffness_n_per_m > 0.0 ? (config::number(p.max_stiffness_n_per_m) + " N/m").c_str() : "not published");
    out += line;
  }
  return out + "(sources, and the figures still to check: " + config::shipped("docs/devices.md") + ", \"Profiles\"; in the code: core/devices/device_profile.cpp)\n";
}

}  // namespace

int devices(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"dhd-library", "hd-library", "hd-device", "inverse3-port"}, {"udev-rules", "profiles"});
  if (a.flag("help")) {
    std::fputs(kDevicesHelp, stdout);
    return 0;
  }
  if (!a.positional.empty()) throw UsageError("unexpected argument '" + a.positional.front() + "'");
  if (a.flag("udev-rules")) {
    std::fputs(devices::usb::udev_rules().c_str(), stdout);
    return 0;
  }
  if (a.flag("profiles")) {
    std::fputs(profiles().c_str(), stdout);
    return 0;
  }
  const double port = a.number("inverse3-port", devices::inverse3::kSimulationPort);
  if (port < 1 || port > 65535 || port != static_cast<int>(port)) throw UsageError("--inverse3-port must be a port number, 1 .. 65535");
  devices::usb::LibusbBus bus;
  const auto found = bus.list();
  std::fputs(devices::usb::report(found).c_str(), stdout);
  const devices::vendor::Presence vendors[] = {
      devices::vendor::probe_dhd(a.get("dhd-library", "libdhd.so")),
      devices::vendor::probe_hd(a.get("hd-library", "libHD.so"), a.get("hd-device")),
      devices::inverse3::probe_inverse3("127.0.0.1", static_cast<int>(port), kServiceTimeout_s),
  };
  bool any = !found.empty();
  std::fputs("\nvendor SDKs and services:\n", stdout);
  for (const auto& v : vendors) {
    std::fputs(v.report.c_str(), stdout);
    any = any || v.present;
  }
  return any ? 0 : 1;
}

}  // namespace enact::cli
