#pragma once
// The real USB bus, over libusb-1.0: an owning libusb context, and a Bus that lists the
// supported devices and opens them. Opening: the device file (/dev/bus/usb/BBB/DDD) is
// opened by us and handed to libusb (libusb_wrap_sys_device), so that the transport keeps a
// file descriptor it can use from a fatal-signal handler (the usbfs ioctls are
// async-signal-safe; libusb is not). Then the configuration is set if asked, a kernel driver
// bound to the interface is detached (ftdi_sio binds the Falcon's FT232; it is re-attached
// on close) and the interface is claimed.
#include <libusb-1.0/libusb.h>

#include <memory>

#include "core/devices/usb/transport.h"

namespace enact::devices::usb {

// owning libusb context (libusb_init / libusb_exit)
class Context {
 public:
  // throws config::Error when libusb cannot start
  Context();
  libusb_context* get() const { return ctx_.get(); }

 private:
  struct Exit {
    void operator()(libusb_context* c) const noexcept { libusb_exit(c); }
  };
  std::unique_ptr<libusb_context, Exit> ctx_;
};

// the machine's USB bus
class LibusbBus final : public Bus {
 public:
  // throws config::Error when libusb cannot start
  LibusbBus();
  // supported devices, with their serial when the device could be opened to read it
  std::vector<Found> list() override;
  Opened open(const Found& device, const Claim& claim) override;

 private:
  std::shared_ptr<Context> context_;  // outlives every transport opened from it
};

// a libusb error code as a Status
Status status_of(int libusb_error);

}  // namespace enact::devices::usb
