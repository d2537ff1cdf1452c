#include "core/devices/vendor/dhd_device.h"

#include <array>
#include <cmath>

#include "core/devices/params_error.h"
#include "core/devices/vendor/frames.h"
#include "core/rt/clock.h"

namespace enact::devices::vendor {
namespace {

constexpr const char* kDevice = "dhd";
constexpr std::int64_t kDeactivateWait_ns = 200'000'000;
constexpr const char* kInstall =
    "install the Force Dimension SDK and set library to its libdhd.so, "
    "or put its folder on LD_LIBRARY_PATH; `enact devices --dhd-library PATH` checks it";

}  // namespace

void DhdApi::bind(const SharedLibrary& library) {
  library.bind("dhdOpen", open);
  library.bind("dhdClose", close);
  library.bind("dhdGetStatus", get_status);
  library.bind("dhdEnableForce", enable_force);
  library.bind("dhdGetPosition", get_position);
  library.bind("dhdGetLinearVelocity", get_linear_velocity);
  library.bind("dhdSetForce", set_force);
  library.bind("dhdGetButtonMask", get_button_mask);
  library.bind("dhdErrorGetLastStr", error_last);
  library.bind("dhdGetDeviceCount", device_count);
}

DhdForceDevice::DhdForceDevice(DhdParams params) : params_(std::move(params)) {}

DhdForceDevice::~DhdForceDevice() { close(); }

void DhdForceDevice::close() noexcept {
  io_.stop();
  if (id_ < 0) return;
  const char id = static_cast<char>(id_);
  api_.set_force(0.0, 0.0, 0.0, id);
  api_.close(id);
  id_ = -1;
}

void DhdForceDevice::configure() {
  close();
  configured_ = false;
  const DhdParams& p = params_;
  require(std::isfinite(p.io_period_s) && p.io_period_s > 0.0 && p.io_period_s <= 0.01, kDevice, "io_period_s", p.io_period_s, "(0, 0.01] s (default 0.00025)");
  require(std::isfinite(p.stale_s) && p.stale_s > 0.0 && p.stale_s <= 0.009, kDevice, "stale_s", p.stale_s, "(0, 0.009] s: faults must show within 10 ms (default 0.005)");
  const auto profile = devices::find_device_profile(p.profile);
  if (!profile) refuse(kDevice, "no device profile '" + p.profile + "'", "set profile to one of `enact devices --profiles` (omega3 for an omega.3)");
  profile_ = *profile;
  library_ = SharedLibrary(p.library, kDevice, kInstall);
  api_.bind(library_);
  // the device: the first one found
  const int id = api_.open();
  if (id < 0) {
    refuse(kDevice, std::string("no Force Dimension device could be opened (") + api_.error_last() + ")",
           "plug the device in and power it on; without root, install the udev rules (enact devices --udev-rules)");
  }
  id_ = id;
  std::array<int, kDhdStatusSlots> status{};
  if (api_.get_status(status.data(), static_cast<char>(id_)) < 0) {
    const std::string why = api_.error_last();
    close();
    refuse(kDevice, "cannot read the device's status (" + why + ")", "unplug and replug the device, then try again");
  }
  if (status[kDhdStatusReset] != 0) {
    close();
    refuse(kDevice, "the device is not calibrated (it is in RESET mode)",
           "calibrate it: run Force Dimension's autoinit tool, or move it to its calibration position as its manual says, then start again");
  }
  if (api_.enable_force(1, static_cast<char>(id_)) < 0) {
    const std::string why = api_.error_last();
    close();
    refuse(kDevice, "cannot enable forces (" + why + ")", "release the device's force button or brake (see its manual), then try again");
  }
  exchange_.reset(std::llround(p.stale_s * 1e9), std::llround(kCommandTimeout_s * 1e9), rt::now_ns());
  io_.start(std::llround(p.io_period_s * 1e9), [this](std::int64_t now) { return io_step(now); });
  configured_ = true;
}

bool DhdForceDevice::io_step(std::int64_t now_ns) noexcept {
  const char id = static_cast<char>(id_);
  math::Vec3 p, v;
  if (api_.get_position(&p.x, &p.y, &p.z, id) < 0 || api_.get_linear_velocity(&v.x, &v.y, &v.z, id) < 0) {
    exchange_.fail();
    return false;
  }
  exchange_.publish({rt::now_ns(), dhd_to_enact(p), dhd_to_enact(v), api_.get_button_mask(id), true});
  const math::Vec3 f = enact_to_dhd(exchange_.command(now_ns));
  if (api_.set_force(f.x, f.y, f.z, id) < 0) {
    exchange_.fail();
    return false;
  }
  return true;
}

void DhdForceDevice::activate() {
  if (!configured_) refuse(kDevice, "activate before configure", "call configure() first");
  exchange_.set_active(true);
}

bool DhdForceDevice::read(std::int64_t now_ns, ForceSample& out) noexcept { return exchange_.read(now_ns, profile_, out); }

void DhdForceDevice::write(std::int64_t, const math::Vec3& force_n) noexcept { exchange_.write(force_n); }

void DhdForceDevice::deactivate() noexcept {
  if (!exchange_.active()) return;
  exchange_.set_active(false);
  exchange_.await_zero(kDeactivateWait_ns);
}

}  // namespace enact::devices::vendor
