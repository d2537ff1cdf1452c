#include "core/devices/usb/libusb.h"

#include <fcntl.h>
#include <linux/usbdevice_fs.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/config/yaml.h"

namespace enact::devices::usb {
namespace {

// the emergency transfers' timeout: long enough for a device that answers, short enough
// that a dying process does not hang on one that does not
constexpr unsigned kEmergencyTimeoutMs = 100;

// owning file descriptor
class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  ~Fd() { reset(); }
  Fd(Fd&& o) noexcept : fd_(o.release()) {}
  Fd& operator=(Fd&& o) noexcept {
    if (this != &o) {
      reset();
      fd_ = o.release();
    }
    return *this;
  }
  int get() const { return fd_; }
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }
  void reset() noexcept {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

struct CloseHandle {
  void operator()(libusb_device_handle* h) const noexcept { libusb_close(h); }
};
using Handle = std::unique_ptr<libusb_device_handle, CloseHandle>;

std::string device_path(int bus, int address) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "/dev/bus/usb/%03d/%03d", bus, address);
  return buf;
}

Status status_of_errno(int err) {
  switch (err) {
    case EACCES:
    case EPERM: return Status::access;
    case ENOENT: return Status::not_found;
    case ENODEV: return Status::no_device;
    case EBUSY: return Status::busy;
    default: return Status::other;
  }
}

// the device file, opened read-write, wrapped in a libusb handle (the handle does not own the fd)
struct Wrapped {
  Fd fd;
  Handle handle;
  Status status = Status::other;
  std::string detail;
};

Wrapped wrap(libusb_context* ctx, const std::string& path) {
  Wrapped w;
  w.fd = Fd(::open(path.c_str(), O_RDWR | O_CLOEXEC));
  if (w.fd.get() < 0) {
    w.status = status_of_errno(errno);
    w.detail = std::string("open ") + path + ": " + std::strerror(errno);
    return w;
  }
  libusb_device_handle* h = nullptr;
  const int rc = libusb_wrap_sys_device(ctx, static_cast<intptr_t>(w.fd.get()), &h);
  if (rc != LIBUSB_SUCCESS) {
    w.status = status_of(rc);
    w.detail = std::string("libusb_wrap_sys_device: ") + libusb_error_name(rc);
    return w;
  }
  w.handle.reset(h);
  w.status = Status::ok;
  return w;
}

// an opened device with its interface claimed; releases it (re-attaching the kernel
// driver it detached) and closes on destruction
class LibusbTransport final : public Transport {
 public:
  LibusbTransport(std::shared_ptr<Context> context, Wrapped wrapped, int interface, bool reattach)
      : context_(std::move(context)), fd_(std::move(wrapped.fd)), handle_(std::move(wrapped.handle)), interface_(interface), reattach_(reattach) {}
  ~LibusbTransport() override {
    libusb_release_interface(handle_.get(), interface_);
    if (reattach_) libusb_attach_kernel_driver(handle_.get(), interface_);
    handle_.reset();  // before the fd it uses
  }

  Outcome control(const ControlSetup& s, std::uint8_t* data, std::uint16_t length, int timeout_ms) noexcept override {
    const int rc = libusb_control_transfer(handle_.get(), s.request_type, s.request, s.value, s.index, data, length, static_cast<unsigned>(timeout_ms));
    return rc >= 0 ? Outcome{Status::ok, rc} : Outcome{status_of(rc), 0};
  }
  Outcome bulk(std::uint8_t endpoint, std::uint8_t* data, int length, int timeout_ms) noexcept override {
    int moved = 0;
    const int rc = libusb_bulk_transfer(handle_.get(), endpoint, data, length, &moved, static_cast<unsigned>(timeout_ms));
    return {rc == 0 ? Status::ok : status_of(rc), moved};
  }
  Outcome interrupt(std::uint8_t endpoint, std::uint8_t* data, int length, int timeout_ms) noexcept override {
    int moved = 0;
    const int rc = libusb_interrupt_transfer(handle_.get(), endpoint, data, length, &moved, static_cast<unsigned>(timeout_ms));
    return {rc == 0 ? Status::ok : status_of(rc), moved};
  }

  // straight usbfs ioctls on our own fd: async-signal-safe
  bool emergency_control_out(const ControlSetup& s, const std::uint8_t* data, std::uint16_t length) noexcept override {
    usbdevfs_ctrltransfer t{};
    t.bRequestType = s.request_type;
    t.bRequest = s.request;
    t.wValue = s.value;
    t.wIndex = s.index;
    t.wLength = length;
    t.timeout = kEmergencyTimeoutMs;
    t.data = const_cast<std::uint8_t*>(data);
    return ::ioctl(fd_.get(), USBDEVFS_CONTROL, &t) >= 0;
  }
  bool emergency_bulk_out(std::uint8_t endpoint, const std::uint8_t* data, int length) noexcept override {
    usbdevfs_bulktransfer t{};
    t.ep = endpoint;
    t.len = static_cast<unsigned>(length);
    t.timeout = kEmergencyTimeoutMs;
    t.data = const_cast<std::uint8_t*>(data);
    return ::ioctl(fd_.get(), USBDEVFS_BULK, &t) >= 0;
  }

 private:
  std::shared_ptr<Context> context_;
  Fd fd_;
  Handle handle_;
  int interface_;
  bool reattach_;
};

// the serial number string of an opened device (empty when it has none)
std::string serial_of(libusb_device_handle* h, std::uint8_t index) {
  if (index == 0) return "";
  unsigned char buf[128];
  const int n = libusb_get_string_descriptor_ascii(h, index, buf, sizeof buf);
  return n > 0 ? std::string(reinterpret_cast<char*>(buf), static_cast<std::size_t>(n)) : "";
}

}  // namespace

Status status_of(int libusb_error) {
  switch (libusb_error) {
    case LIBUSB_SUCCESS: return Status::ok;
    case LIBUSB_ERROR_TIMEOUT: return Status::timeout;
    case LIBUSB_ERROR_NO_DEVICE: return Status::no_device;
    case LIBUSB_ERROR_PIPE: return Status::stall;
    case LIBUSB_ERROR_IO:
    case LIBUSB_ERROR_OVERFLOW: return Status::io;
    case LIBUSB_ERROR_ACCESS: return Status::access;
    case LIBUSB_ERROR_NOT_FOUND: return Status::not_found;
    case LIBUSB_ERROR_BUSY: return Status::busy;
    default: return Status::other;
  }
}

Context::Context() {
  libusb_context* c = nullptr;
  const int rc = libusb_init(&c);
  if (rc != LIBUSB_SUCCESS) {
    throw config::Error(std::string("USB is not available: libusb_init failed: ") + libusb_error_name(rc) +
                        "\n  fix: check that /dev/bus/usb exists (in a container, pass the host's /dev/bus/usb through)");
  }
  ctx_.reset(c);
}

LibusbBus::LibusbBus() : context_(std::make_shared<Context>()) {}

std::vector<Found> LibusbBus::list() {
  std::vector<Found> out;
  libusb_device** devices = nullptr;
  const ssize_t n = libusb_get_device_list(context_->get(), &devices);
  if (n < 0) return out;
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor desc{};
    if (libusb_get_device_descriptor(devices[i], &desc) != LIBUSB_SUCCESS) continue;
    bool known = false;
    for (const auto& s : supported_devices()) known = known || (s.vendor == desc.idVendor && s.product == desc.idProduct);
    if (!known) continue;
    Found f;
    f.vendor = desc.idVendor;
    f.product = desc.idProduct;
    f.bus = libusb_get_bus_number(devices[i]);
    f.address = libusb_get_device_address(devices[i]);
    f.path = device_path(f.bus, f.address);
    // opening it tells whether we may, and gives the serial
    Wrapped w = wrap(context_->get(), f.path);
    f.access = w.status;
    if (w.status == Status::ok) f.serial = serial_of(w.handle.get(), desc.iSerialNumber);
    out.push_back(f);
  }
  libusb_free_device_list(devices, 1);
  return out;
}

Opened LibusbBus::open(const Found& device, const Claim& claim) {
  Opened out;
  Wrapped w = wrap(context_->get(), device.path);
  if (w.status != Status::ok) {
    out.status = w.status;
    out.detail = w.detail;
    return out;
  }
  libusb_device_handle* h = w.handle.get();
  auto fail = [&](const char* step, int rc) {
    out.status = status_of(rc);
    out.detail = std::string(step) + ": " + libusb_error_name(rc);
    return std::move(out);
  };
  // the configuration, if asked and not already set
  if (claim.configuration >= 0) {
    int current = -1;
    if (const int rc = libusb_get_configuration(h, &current); rc != LIBUSB_SUCCESS) return fail("libusb_get_configuration", rc);
    if (current != claim.configuration) {
      if (const int rc = libusb_set_configuration(h, claim.configuration); rc != LIBUSB_SUCCESS) return fail("libusb_set_configuration", rc);
    }
  }
  // a kernel driver on the interface (ftdi_sio on the Falcon) goes, to come back on close
  bool reattach = false;
  if (libusb_kernel_driver_active(h, claim.interface) == 1) {
    if (const int rc = libusb_detach_kernel_driver(h, claim.interface); rc != LIBUSB_SUCCESS) return fail("libusb_detach_kernel_driver", rc);
    reattach = true;
  }
  if (const int rc = libusb_claim_interface(h, claim.interface); rc != LIBUSB_SUCCESS) {
    if (reattach) libusb_attach_kernel_driver(h, claim.interface);
    return fail("libusb_claim_interface", rc);
  }
  out.transport = std::make_unique<LibusbTransport>(context_, std::move(w), claim.interface, reattach);
  out.status = Status::ok;
  return out;
}

}  // namespace enact::devices::usb
