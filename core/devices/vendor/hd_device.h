#pragma once
// 3D Systems Touch, Touch X and other OpenHaptics devices as a ForceDevice (`device: hd`),
// through the OpenHaptics HD C API loaded at run time from `library` (default libHD.so;
// enact builds and runs without it).
//
// The HD API runs the device from its own servo thread (the "scheduler", about 1 kHz): all
// device state is read and forces are set inside a callback it calls, between hdBeginFrame
// and hdEndFrame (OpenHaptics Programmer's Guide, "the servo loop"). So our callback is
// the I/O side of the shared exchange (core/devices/io_exchange.h): it publishes position, velocity and
// buttons and sets the force the loop last wrote; the real-time loop never calls HD.
// Functions bound (hd.h): hdInitDevice, hdDisableDevice, hdGetError, hdGetErrorString,
// hdBeginFrame, hdEndFrame, hdGetDoublev, hdGetIntegerv, hdSetDoublev, hdEnable,
// hdCheckCalibration, hdScheduleAsynchronous, hdUnschedule, hdStartScheduler,
// hdStopScheduler. An HD error in the callback is a device error: the callback stops.
//
// configure(): load and bind, hdInitDevice (the default device, or `device_name` from Touch
// Setup), enable force output, schedule the callback, start the scheduler, then wait for
// the first callback's calibration check: a device whose calibration is not OK is refused
// (the fix: the inkwell, or Touch Diagnostic). The destructor stops the scheduler,
// unschedules the callback and disables the device.
#include <atomic>
#include <cstdint>
#include <string>

#include "core/devices/device.h"
#include "core/devices/io_exchange.h"
#include "core/devices/vendor/shared_library.h"

namespace enact::devices::vendor {

struct HdParams {
  std::string library = "libHD.so";  // the OpenHaptics library: a file name (searched) or a path
  std::string device_name;           // the device's name in Touch Setup (empty: the default device)
  std::string profile = "touch";     // the device profile (workspace, forces, limits)
  double stale_s = 0.005;            // (0, 0.009]: a sample older than this is a device error
};

// HD's types and constants (hdDefines.h, OpenHaptics 3.x; the same values in every
// independent reading of it we found; to check against your SDK's header)
using HHD = unsigned int;
using HDenum = unsigned int;
using HDSchedulerHandle = unsigned long;
using HDCallbackCode = unsigned int;
struct HDErrorInfo {
  unsigned int errorCode;
  int internalErrorCode;
  HHD hHD;
};
constexpr unsigned int kHdSuccess = 0x0000;
constexpr HHD kHdInvalidHandle = 0xFFFFFFFFu;
constexpr HDenum kHdCurrentButtons = 0x2000;
constexpr HDenum kHdCurrentPosition = 0x2050;
constexpr HDenum kHdCurrentVelocity = 0x2051;
constexpr HDenum kHdCurrentForce = 0x2700;
constexpr HDenum kHdForceOutput = 0x4000;
constexpr HDenum kHdCalibrationOk = 0x5000;
constexpr HDCallbackCode kHdCallbackDone = 0;
constexpr HDCallbackCode kHdCallbackContinue = 1;
constexpr unsigned short kHdMaxSchedulerPriority = 0xffff;

// the HD functions enact calls (signatures of hd.h)
struct HdApi {
  HHD (*init_device)(const char* name) = nullptr;
  void (*disable_device)(HHD) = nullptr;
  HDErrorInfo (*get_error)() = nullptr;
  const char* (*error_string)(unsigned int code) = nullptr;
  void (*begin_frame)(HHD) = nullptr;
  void (*end_frame)(HHD) = nullptr;
  void (*get_doublev)(HDenum, double*) = nullptr;
  void (*get_integerv)(HDenum, int*) = nullptr;
  void (*set_doublev)(HDenum, const double*) = nullptr;
  void (*enable)(HDenum) = nullptr;
  HDenum (*check_calibration)() = nullptr;
  HDSchedulerHandle (*schedule_asynchronous)(HDCallbackCode (*)(void*), void*, unsigned short) = nullptr;
  void (*unschedule)(HDSchedulerHandle) = nullptr;
  void (*start_scheduler)() = nullptr;
  void (*stop_scheduler)() = nullptr;
  // bind every function of `library`; throws config::Error
  void bind(const SharedLibrary& library);
  // the last HD error as text ("" when none)
  std::string last_error() const;
};

class HdForceDevice final : public ForceDevice {
 public:
  explicit HdForceDevice(HdParams params);
  ~HdForceDevice() override;
  HdForceDevice(const HdForceDevice&) = delete;
  HdForceDevice& operator=(const HdForceDevice&) = delete;

  void configure() override;
  void activate() override;
  bool read(std::int64_t now_ns, ForceSample& out) noexcept override;
  void write(std::int64_t now_ns, const math::Vec3& force_n) noexcept override;
  void deactivate() noexcept override;
  const devices::DeviceProfile& profile() const override { return profile_; }

  // servo callbacks run since configure
  std::uint64_t servo_ticks() const { return ticks_.load(); }

  // how long write() may stay silent before the servo callback zeroes the force on its own
  static constexpr double kCommandTimeout_s = 0.020;

 private:
  enum class Calibration : int { unknown, ok, needed };
  static HDCallbackCode servo(void* self) noexcept;
  HDCallbackCode servo_tick() noexcept;
  void close() noexcept;

  HdParams params_;
  devices::DeviceProfile profile_;
  SharedLibrary library_;
  HdApi api_;
  HHD device_ = kHdInvalidHandle;
  HDSchedulerHandle callback_ = 0;
  bool scheduled_ = false;
  IoExchange exchange_;
  std::atomic<Calibration> calibration_{Calibration::unknown};
  std::atomic<std::uint64_t> ticks_{0};
  bool configured_ = false;
};

}  // namespace enact::devices::vendor
