#include "core/devices/vendor/hd_device.h"

#include <array>
#include <chrono>
#include <cmath>
#include <thread>

#include "core/devices/params_error.h"
#include "core/devices/vendor/frames.h"
#include "core/rt/clock.h"

namespace enact::devices::vendor {
namespace {

constexpr const char* kHd = "hd";
constexpr std::int64_t kHdDeactivateWait_ns = 200'000'000;
constexpr std::int64_t kFirstCallbackWait_ns = 2'000'000'000;  // the scheduler's first servo tick
constexpr const char* kHdInstall =
    "install OpenHaptics for Linux and the Touch device driver, and set library to its libHD.so, "
    "or put its folder on LD_LIBRARY_PATH; `enact devices --hd-library PATH` checks it";

}  // namespace

void HdApi::bind(const SharedLibrary& library) {
  library.bind("hdInitDevice", init_device);
  library.bind("hdDisableDevice", disable_device);
  library.bind("hdGetError", get_error);
  library.bind("hdGetErrorString", error_string);
  library.bind("hdBeginFrame", begin_frame);
  library.bind("hdEndFrame", end_frame);
  library.bind("hdGetDoublev", get_doublev);
  library.bind("hdGetIntegerv", get_integerv);
  library.bind("hdSetDoublev", set_doublev);
  library.bind("hdEnable", enable);
  library.bind("hdCheckCalibration", check_calibration);
  library.bind("hdScheduleAsynchronous", schedule_asynchronous);
  library.bind("hdUnschedule", unschedule);
  library.bind("hdStartScheduler", start_scheduler);
  library.bind("hdStopScheduler", stop_scheduler);
}

std::string HdApi::last_error() const {
  const HDErrorInfo e = get_error();
  if (e.errorCode == kHdSuccess) return "";
  const char* text = error_string(e.errorCode);
  return std::string(text ? text : "HD error") + " (code " + std::to_string(e.errorCode) + ")";
}

HdForceDevice::HdForceDevice(HdParams params) : params_(std::move(params)) {}

HdForceDevice::~HdForceDevice() { close(); }

void HdForceDevice::close() noexcept {
  if (scheduled_) {
    api_.stop_scheduler();
    api_.unschedule(callback_);
    scheduled_ = false;
  }
  if (device_ != kHdInvalidHandle) {
    api_.disable_device(device_);
    device_ = kHdInvalidHandle;
  }
}

void HdForceDevice::configure() {
  close();
  configured_ = false;
  const HdParams& p = params_;
  require(std::isfinite(p.stale_s) && p.stale_s > 0.0 && p.stale_s <= 0.009, kHd, "stale_s", p.stale_s, "(0, 0.009] s: faults must show within 10 ms (default 0.005)");
  const auto profile = devices::find_device_profile(p.profile);
  if (!profile) refuse(kHd, "no device profile '" + p.profile + "'", "set profile to one of `enact devices --profiles` (touch for a Touch)");
  profile_ = *profile;
  library_ = SharedLibrary(p.library, kHd, kHdInstall);
  api_.bind(library_);
  // the device
  device_ = api_.init_device(p.device_name.empty() ? nullptr : p.device_name.c_str());
  if (const std::string why = api_.last_error(); !why.empty() || device_ == kHdInvalidHandle) {
    device_ = kHdInvalidHandle;
    refuse(kHd, "cannot open the device" + (p.device_name.empty() ? std::string() : " '" + p.device_name + "'") + ": " + why,
           "plug the Touch in, check it in Touch Setup (its name there is device_name; empty: the default device), and that you may open its device file");
  }
  api_.enable(kHdForceOutput);
  // the servo callback, then the scheduler
  exchange_.reset(std::llround(p.stale_s * 1e9), std::llround(kCommandTimeout_s * 1e9), rt::now_ns());
  calibration_.store(Calibration::unknown);
  ticks_.store(0);
  callback_ = api_.schedule_asynchronous(&HdForceDevice::servo, this, kHdMaxSchedulerPriority);
  scheduled_ = true;
  api_.start_scheduler();
  if (const std::string why = api_.last_error(); !why.empty()) {
    close();
    refuse(kHd, "cannot start the servo scheduler: " + why, "close other programs using the device (Touch Diagnostic), then try again");
  }
  // the first tick says whether the device is calibrated
  const std::int64_t give_up = rt::now_ns() + kFirstCallbackWait_ns;
  while (calibration_.load() == Calibration::unknown && !exchange_.failed() && rt::now_ns() < give_up) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (calibration_.load() != Calibration::ok) {
    const bool silent = calibration_.load() == Calibration::unknown;
    close();
    if (silent) refuse(kHd, "the servo scheduler did not run", "check the device in Touch Diagnostic, then try again");
    refuse(kHd, "the device is not calibrated", "put the stylus in its inkwell (Touch), or calibrate it in Touch Diagnostic, then start again");
  }
  configured_ = true;
}

HDCallbackCode HdForceDevice::servo(void* self) noexcept { return static_cast<HdForceDevice*>(self)->servo_tick(); }

HDCallbackCode HdForceDevice::servo_tick() noexcept {
  const std::int64_t now = rt::now_ns();
  api_.begin_frame(device_);
  if (calibration_.load(std::memory_order_relaxed) == Calibration::unknown) {
    calibration_.store(api_.check_calibration() == kHdCalibrationOk ? Calibration::ok : Calibration::needed);
  }
  std::array<double, 3> p_mm{}, v_mm_per_s{};
  int buttons = 0;
  api_.get_doublev(kHdCurrentPosition, p_mm.data());
  api_.get_doublev(kHdCurrentVelocity, v_mm_per_s.data());
  api_.get_integerv(kHdCurrentButtons, &buttons);
  exchange_.publish({now, hd_mm_to_enact_m({p_mm[0], p_mm[1], p_mm[2]}), hd_mm_to_enact_m({v_mm_per_s[0], v_mm_per_s[1], v_mm_per_s[2]}),
                     static_cast<std::uint32_t>(buttons), true});
  const math::Vec3 f = enact_to_hd_force(exchange_.command(now));
  const std::array<double, 3> f_n{f.x, f.y, f.z};
  api_.set_doublev(kHdCurrentForce, f_n.data());
  api_.end_frame(device_);
  ticks_.fetch_add(1);
  if (api_.get_error().errorCode != kHdSuccess) {
    exchange_.fail();
    return kHdCallbackDone;
  }
  return kHdCallbackContinue;
}

void HdForceDevice::activate() {
  if (!configured_) refuse(kHd, "activate before configure", "call configure() first");
  exchange_.set_active(true);
}

bool HdForceDevice::read(std::int64_t now_ns, ForceSample& out) noexcept { return exchange_.read(now_ns, profile_, out); }

void HdForceDevice::write(std::int64_t, const math::Vec3& force_n) noexcept { exchange_.write(force_n); }

void HdForceDevice::deactivate() noexcept {
  if (!exchange_.active()) return;
  exchange_.set_active(false);
  exchange_.await_zero(kHdDeactivateWait_ns);
}

}  // namespace enact::devices::vendor
