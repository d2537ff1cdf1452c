#include "core/devices/usb/transport.h"

#include <cstdio>
#include <stdexcept>

#include "core/config/yaml.h"

namespace enact::devices::usb {

Transport::~Transport() = default;
Bus::~Bus() = default;

const char* to_string(Status status) {
  switch (status) {
    case Status::ok: return "ok";
    case Status::timeout: return "timeout";
    case Status::no_device: return "no device (unplugged)";
    case Status::stall: return "stall (request refused)";
    case Status::io: return "i/o error";
    case Status::access: return "permission denied";
    case Status::not_found: return "not found";
    case Status::busy: return "busy (claimed by another program or driver)";
    case Status::other: return "error";
  }
  return "error";
}

const std::vector<SupportedDevice>& supported_devices() {
  // Novint Falcon: USB id 0403:cb48 (FTDI's vendor id, Novint's product id), as libnifalcon
  // matches it (libnifalcon, src/comm/FalconCommLibUSB.cpp, BSD). Metec Braille cells: USB id
  // 0452:0100, as BRLTTY's Metec driver matches them (Drivers/Braille/Metec/braille.c).
  static const std::vector<SupportedDevice> devices = {
      {0x0403, 0xcb48, "falcon", "Novint Falcon"},
      {0x0452, 0x0100, "metec", "Metec Braille cells"},
  };
  return devices;
}

const SupportedDevice& supported(const std::string& backend) {
  for (const auto& d : supported_devices()) {
    if (backend == d.backend) return d;
  }
  throw std::invalid_argument("no supported USB device for backend '" + backend + "'");
}

std::string usb_id(std::uint16_t vendor, std::uint16_t product) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04x:%04x", vendor, product);
  return buf;
}

std::string udev_rules() {
  std::string out =
      "# enact: access for the logged-in user (uaccess) and the plugdev group to its USB devices.\n"
      "# Install (as root): cp 99-enact.rules /etc/udev/rules.d/ && udevadm control --reload-rules && udevadm trigger\n"
      "# (written by `enact devices --udev-rules`)\n";
  for (const auto& d : supported_devices()) {
    const std::string id = usb_id(d.vendor, d.product);
    out += "# " + std::string(d.name) + " (" + id + ", device: " + d.backend + ")\n";
    out += "SUBSYSTEM==\"usb\", ATTRS{idVendor}==\"" + id.substr(0, 4) + "\", ATTRS{idProduct}==\"" + id.substr(5) +
           "\", MODE=\"0660\", GROUP=\"plugdev\", TAG+=\"uaccess\"\n";
  }
  return out;
}

std::string udev_fix() {
  return "install enact's udev rules (as root): cp scripts/udev/99-enact.rules /etc/udev/rules.d/ && udevadm control --reload-rules && "
         "udevadm trigger, then unplug and replug the device (or add yourself to the plugdev group). The rules:\n" +
         udev_rules();
}

std::string report(const std::vector<Found>& devices) {
  std::string out;
  bool denied = false;
  for (const Found& f : devices) {
    for (const auto& kind : supported_devices()) {
      if (kind.vendor != f.vendor || kind.product != f.product) continue;
      char line[512];
      std::snprintf(line, sizeof line, "%s  %-20s  %-22s  serial %-12s  device: %-7s  %s\n", usb_id(f.vendor, f.product).c_str(), kind.name, f.path.c_str(),
                    f.serial.empty() ? "?" : f.serial.c_str(), kind.backend, f.access == Status::ok ? "ready" : to_string(f.access));
      out += line;
      denied = denied || f.access == Status::access;
    }
  }
  if (out.empty()) {
    out = "no supported USB device found. enact looks for:\n";
    for (const auto& kind : supported_devices()) out += "  " + usb_id(kind.vendor, kind.product) + "  " + kind.name + " (device: " + kind.backend + ")\n";
    out += "Plug one in (and power it on). Without hardware, the emulators stand in: transport=emulator (launch/bridge_rt_usb_emulated.yaml).\n";
  }
  if (denied) out += "\nPermission denied: enact may not open a device above.\n  fix: " + udev_fix();
  return out;
}

namespace {

[[noreturn]] void refuse(const std::string& problem, const std::string& fix) { throw config::Error(problem + "\n  fix: " + fix); }

std::string where(const Found& f) { return f.path.empty() ? "bus " + std::to_string(f.bus) + " device " + std::to_string(f.address) : f.path; }

}  // namespace

std::unique_ptr<Transport> open_device(Bus& bus, const std::string& backend, const std::string& serial, const Claim& claim) {
  const SupportedDevice& kind = supported(backend);
  const std::string what = std::string(kind.name) + " (USB " + usb_id(kind.vendor, kind.product) + ")";
  // the devices of this kind, the one with the serial if given
  std::vector<Found> candidates;
  std::string serials;
  for (const Found& f : bus.list()) {
    if (f.vendor != kind.vendor || f.product != kind.product) continue;
    serials += (serials.empty() ? "" : ", ") + (f.serial.empty() ? "(unknown)" : f.serial);
    if (serial.empty() || f.serial == serial) candidates.push_back(f);
  }
  if (candidates.empty() && serials.empty()) {
    refuse("no " + what + " found on the USB bus",
           "plug it in (and power it on); `enact devices` lists what enact finds; or run without hardware: transport=emulator");
  }
  if (candidates.empty()) {
    refuse("no " + what + " with serial '" + serial + "' (found: " + serials + ")", "set serial to one of the serials found, or leave it empty");
  }
  // open it; say plainly why not
  const Found& f = candidates.front();
  Opened opened = bus.open(f, claim);
  switch (opened.status) {
    case Status::ok: return std::move(opened.transport);
    case Status::access:
      refuse("permission denied opening the " + what + " at " + where(f) + (opened.detail.empty() ? "" : " (" + opened.detail + ")"), udev_fix());
    case Status::busy:
      refuse("the " + what + " at " + where(f) + " is claimed by another program or driver" + (opened.detail.empty() ? "" : " (" + opened.detail + ")"),
             backend == "metec" ? "stop the program using it (BRLTTY drives Metec displays: systemctl stop brltty)" : "close the program using it");
    case Status::no_device:
    case Status::not_found:
      refuse("the " + what + " at " + where(f) + " disappeared while opening it", "check the cable and the device's power, then try again");
    default:
      refuse("cannot open the " + what + " at " + where(f) + ": " + to_string(opened.status) + (opened.detail.empty() ? "" : " (" + opened.detail + ")"),
             "unplug and replug the device; `enact devices` shows whether enact can see and open it");
  }
}

}  // namespace enact::devices::usb
