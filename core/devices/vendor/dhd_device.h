#pragma once
// Force Dimension devices (omega, delta, sigma, and the Novint Falcon through Force
// Dimension's SDK) as a ForceDevice (`device: dhd`), through the SDK's DHD C API loaded at
// run time from `library` (default libdhd.so; enact builds and runs without it).
//
// The DHD API has no scheduler of its own: the application polls the device. So an I/O
// thread of ours (usb::IoThread, every io_period_s) reads position, velocity and buttons
// and sends the force the loop last wrote, through the shared exchange (core/devices/io_exchange.h), so the
// real-time loop never waits on a USB call. The functions bound (Force Dimension SDK
// reference, dhdc.h): dhdOpen, dhdClose, dhdGetStatus (the calibration state: a device in
// RESET mode is not calibrated; to check on a device), dhdEnableForce, dhdGetPosition,
// dhdGetLinearVelocity, dhdSetForce, dhdGetButtonMask, dhdErrorGetLastStr. A call that
// returns < 0 is a device error: the thread stops, reads say device_error.
//
// configure(): load and bind (config::Error naming the missing file or function), open the
// first device, refuse an uncalibrated one (with the fix), enable forces, start the thread
// with zero force. deactivate(): zero, and wait (at most 200 ms) for a zero to go out. The
// destructor stops the thread, sends zero force and closes the device.
#include <cstdint>
#include <string>

#include "core/devices/device.h"
#include "core/devices/usb/io_thread.h"
#include "core/devices/io_exchange.h"
#include "core/devices/vendor/shared_library.h"

namespace enact::devices::vendor {

struct DhdParams {
  std::string library = "libdhd.so";  // the SDK's library: a file name (searched) or a path
  std::string profile = "omega3";     // the device profile (workspace, forces, limits)
  double io_period_s = 0.00025;       // (0, 0.01]: the I/O thread's period (4 kHz)
  double stale_s = 0.005;             // (0, 0.009]: a sample older than this is a device error
};

// the DHD functions enact calls (signatures of dhdc.h; ID -1: the default device)
struct DhdApi {
  int (*open)() = nullptr;
  int (*close)(char id) = nullptr;
  int (*get_status)(int* status, char id) = nullptr;
  int (*enable_force)(unsigned char on, char id) = nullptr;
  int (*get_position)(double* x, double* y, double* z, char id) = nullptr;
  int (*get_linear_velocity)(double* x, double* y, double* z, char id) = nullptr;
  int (*set_force)(double x, double y, double z, char id) = nullptr;
  unsigned int (*get_button_mask)(char id) = nullptr;
  const char* (*error_last)() = nullptr;
  int (*device_count)() = nullptr;
  // bind every function of `library`; throws config::Error
  void bind(const SharedLibrary& library);
};

// the index of DHD_STATUS_RESET in dhdGetStatus' array (dhdc.h)
constexpr int kDhdStatusReset = 3;
// dhdGetStatus' array is DHD_MAX_STATUS long, which grew with the SDK's versions (12 .. 17):
// ours is larger than any
constexpr int kDhdStatusSlots = 64;

class DhdForceDevice final : public ForceDevice {
 public:
  explicit DhdForceDevice(DhdParams params);
  ~DhdForceDevice() override;
  DhdForceDevice(const DhdForceDevice&) = delete;
  DhdForceDevice& operator=(const DhdForceDevice&) = delete;

  void configure() override;
  void activate() override;
  bool read(std::int64_t now_ns, ForceSample& out) noexcept override;
  void write(std::int64_t now_ns, const math::Vec3& force_n) noexcept override;
  void deactivate() noexcept override;
  const devices::DeviceProfile& profile() const override { return profile_; }

  // how long write() may stay silent before the I/O thread zeroes the force on its own
  static constexpr double kCommandTimeout_s = 0.020;

 private:
  void close() noexcept;
  bool io_step(std::int64_t now_ns) noexcept;

  DhdParams params_;
  devices::DeviceProfile profile_;
  SharedLibrary library_;
  DhdApi api_;
  int id_ = -1;  // the device's ID from dhdOpen; -1: none open
  IoExchange exchange_;
  usb::IoThread io_;
  bool configured_ = false;
};

}  // namespace enact::devices::vendor
