#pragma once
// The USB layer under the device backends: a small Transport interface (one opened device,
// its interface claimed: control, bulk and interrupt transfers with timeouts), a Bus that
// lists and opens devices, and the table of supported devices. Two implementations: libusb
// (core/devices/usb/libusb.h, the real bus) and a fake that plays a device emulator at the
// packet level (core/devices/usb/fake.h), so everything above runs without hardware.
//
// Transfers never throw and allocate nothing: they return an Outcome. A device that was
// unplugged answers Status::no_device to every transfer from then on (libusb's
// LIBUSB_ERROR_NO_DEVICE), which is how backends detect hot-unplug.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace enact::devices::usb {

// the result of a transfer or of opening a device (libusb's error codes, by meaning)
enum class Status {
  ok,
  timeout,    // nothing (or not everything) moved within the timeout
  no_device,  // the device is gone (unplugged)
  stall,      // the device refused the request (endpoint halted)
  io,         // transfer error
  access,     // permission denied (opening)
  not_found,  // no such device (opening)
  busy,       // claimed by another program or kernel driver (opening)
  other,
};
const char* to_string(Status status);

struct Outcome {
  Status status = Status::ok;
  int bytes = 0;  // bytes transferred (also on a timeout: what moved before it)
  bool ok() const { return status == Status::ok; }
};

// bmRequestType values of vendor requests to the device (USB 2.0, 9.3.1)
constexpr std::uint8_t kVendorOut = 0x40;
constexpr std::uint8_t kVendorIn = 0xC0;

// the setup stage of a control transfer; bit 7 of request_type: data from the device
struct ControlSetup {
  std::uint8_t request_type = kVendorOut;
  std::uint8_t request = 0;
  std::uint16_t value = 0;
  std::uint16_t index = 0;
};

// one opened USB device with its interface claimed
class Transport {
 public:
  virtual ~Transport();
  // a control transfer on endpoint 0; `data` is sent or filled as setup.request_type says
  virtual Outcome control(const ControlSetup& setup, std::uint8_t* data, std::uint16_t length, int timeout_ms) noexcept = 0;
  // a bulk transfer; endpoint bit 7 set (0x81): from the device into `data`
  virtual Outcome bulk(std::uint8_t endpoint, std::uint8_t* data, int length, int timeout_ms) noexcept = 0;
  // an interrupt transfer, as bulk
  virtual Outcome interrupt(std::uint8_t endpoint, std::uint8_t* data, int length, int timeout_ms) noexcept = 0;
  // Last words for a fatal-signal handler: the same transfers, host to device only, made
  // with async-signal-safe calls (no locks, no allocation); true when the device took it.
  virtual bool emergency_control_out(const ControlSetup& setup, const std::uint8_t* data, std::uint16_t length) noexcept = 0;
  virtual bool emergency_bulk_out(std::uint8_t endpoint, const std::uint8_t* data, int length) noexcept = 0;
};

// a device type enact supports
struct SupportedDevice {
  std::uint16_t vendor;
  std::uint16_t product;
  const char* backend;  // the `device:` parameter that drives it
  const char* name;
};
// the Novint Falcon (an FTDI FT232 bridge with Novint's product id) and Metec Braille cells
const std::vector<SupportedDevice>& supported_devices();
// the entry of a backend ("falcon", "metec"); throws std::invalid_argument for another name
const SupportedDevice& supported(const std::string& backend);

// a device seen on the bus
struct Found {
  std::uint16_t vendor = 0;
  std::uint16_t product = 0;
  int bus = 0;
  int address = 0;
  std::string path;    // the device file (/dev/bus/usb/BBB/DDD), or the fake's name
  std::string serial;  // empty when unknown
  Status access = Status::ok;  // could it be opened (ok, access: permission denied, ...)
};

// what to claim when opening
struct Claim {
  int configuration = -1;  // set this configuration first (-1: leave it)
  int interface = 0;
};

struct Opened {
  std::unique_ptr<Transport> transport;  // null unless status is ok
  Status status = Status::other;
  std::string detail;  // what failed, for messages
};

// the devices on a bus
class Bus {
 public:
  virtual ~Bus();
  // the devices with a supported vendor:product
  virtual std::vector<Found> list() = 0;
  // open a listed device: claim its interface (detaching a kernel driver first)
  virtual Opened open(const Found& device, const Claim& claim) = 0;
};

// find and open the device of `backend` (the one with `serial`, or the first when empty);
// throws config::Error naming the problem and the fix: device absent, permission denied
// (with the udev rule to install), busy, gone
std::unique_ptr<Transport> open_device(Bus& bus, const std::string& backend, const std::string& serial, const Claim& claim);

// the udev rule lines that give the logged-in user access to every supported device (the
// file scripts/udev/99-enact.rules holds the same lines)
std::string udev_rules();
// how to install them
std::string udev_fix();

// what `enact devices` prints for the supported devices found on a bus: one line per device
// (id, name, where, serial, the `device:` backend, and whether enact may open it), or that
// none was found and what enact looks for; the udev rules and how to install them when one
// could not be opened for lack of permission
std::string report(const std::vector<Found>& devices);

// "vvvv:pppp", lower-case hex
std::string usb_id(std::uint16_t vendor, std::uint16_t product);

}  // namespace enact::devices::usb
