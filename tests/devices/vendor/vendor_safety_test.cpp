// The safety layer (core/devices/safety.h) holds for the vendor backends as for the Falcon:
// each backend, on its fake library (DHD, HD) or its emulated service (Inverse3), wrapped in
// SafeForceDevice: a command over the peak force is clamped to the device profile's peak,
// NaN gives no force, a silent loop trips the watchdog and the device gets zero, a jump is
// slew-limited to the profile's step, and the force is zero when the device goes away. What
// is checked is what the device got. And the loop's read and write, through the safety
// layer, allocate nothing on any of them.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <thread>

#include "core/devices/inverse3/emulator.h"
#include "core/devices/inverse3/inverse3_device.h"
#include "core/devices/safety.h"
#include "core/devices/vendor/dhd_device.h"
#include "core/devices/vendor/hd_device.h"
#include "core/rt/clock.h"
#include "tests/devices/vendor/fake_library.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/test_util.h"

namespace enact::devices::vendor {
namespace {

using math::Vec3;

// a backend and what its device does: the force acting on the handle (the device's frame,
// N; compared by magnitude, the frame's tests are elsewhere), whether the device is open
struct Rig {
  std::unique_ptr<ForceDevice> device;
  std::function<Vec3()> force_n;
  std::function<bool()> open;
};

struct Backend {
  const char* name;
  std::function<Rig()> make;
};

// a backend of a fake vendor library, its levers set to a present, calibrated device
template <class Device, class Params>
Backend on_fake(const char* name, const char* library) {
  return {name, [library] {
            auto fake = std::make_shared<test::FakeLibrary>(library);
            fake->set_up();
            Params p;
            p.library = library;
            return Rig{std::make_unique<Device>(p), [fake] { return fake->force_n(); }, [fake] { return fake->is_open() != 0; }};
          }};
}

Backend on_emulated_service() {
  return {"inverse3", [] {
            auto emu = std::make_shared<inverse3::Inverse3Emulator>(inverse3::Inverse3EmulatorParams{});
            inverse3::Inverse3Params p;
            p.port = emu->port();
            p.events_port = emu->events_port();
            p.reply_timeout_s = 1.0;  // a sanitized build on a busy machine can hold the service longer than 0.1 s
            return Rig{std::make_unique<inverse3::Inverse3ForceDevice>(p), [emu] { return emu->force_n(); }, [emu] { return emu->connections() > 0; }};
          }};
}

class VendorSafety : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    Rig rig = GetParam().make();
    device_force_n = rig.force_n;
    device_open = rig.open;
    SafetyParams s;
    s.reengage_s = 0.0;  // no ramp back after activation: the limits alone shape the force
    safe = std::make_unique<SafeForceDevice>(std::move(rig.device), s);
    safe->configure();
    safe->activate();
  }
  // write f about every millisecond until done() or timeout_s, with a read after each
  bool drive(const Vec3& f, const std::function<bool()>& done, double timeout_s = 2.0) {
    ForceSample s;
    return test::eventually([&] {
      safe->write(rt::now_ns(), f);
      safe->read(rt::now_ns(), s);
      return done();
    }, timeout_s);
  }
  // what the device does (the fake library or the emulator outlives the device)
  std::function<Vec3()> device_force_n;
  std::function<bool()> device_open;
  std::unique_ptr<SafeForceDevice> safe;
};

TEST_P(VendorSafety, ACommandOverThePeakIsClampedToTheProfilesPeak) {
  const double peak = safe->profile().peak_force_n;
  ASSERT_GT(peak, 0.0);
  double most = 0.0;
  ASSERT_TRUE(drive({100.0, 0.0, 0.0}, [&] {
    most = std::max(most, math::norm(device_force_n()));
    return std::abs(math::norm(device_force_n()) - peak) < 1e-9;
  })) << most;
  EXPECT_LE(most, peak + 1e-9);
  ForceSample s;
  safe->read(rt::now_ns(), s);
  EXPECT_TRUE(has(s.faults, DeviceFault::clamped));
  EXPECT_GT(safe->clamps(), 0u);
}

TEST_P(VendorSafety, ANanCommandGivesNoForce) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int i = 0; i < 40; ++i) {
    safe->write(rt::now_ns(), {nan, 1.0, 0.0});
    std::this_thread::sleep_for(std::chrono::microseconds(500));
    ASSERT_EQ(math::norm(device_force_n()), 0.0);
  }
  ForceSample s;
  safe->read(rt::now_ns(), s);
  EXPECT_TRUE(has(s.faults, DeviceFault::nonfinite_command));
}

TEST_P(VendorSafety, ASilentLoopTripsTheWatchdogAndTheDeviceGetsZero) {
  ASSERT_TRUE(drive({0.0, 0.0, 1.0}, [&] { return std::abs(math::norm(device_force_n()) - 1.0) < 1e-9; }));
  // reads go on, writes stop: after 10 ms the watchdog ramps the force to zero over 5 ms
  ForceSample s;
  ASSERT_TRUE(test::eventually([&] {
    safe->read(rt::now_ns(), s);
    return has(s.faults, DeviceFault::watchdog) && math::norm(device_force_n()) == 0.0;
  }, 1.0));
  EXPECT_EQ(safe->watchdog_trips(), 1u);
}

TEST_P(VendorSafety, AJumpIsLimitedToTheProfilesForceStep) {
  const double step_n = safe->profile().max_force_step_n_per_ms;  // at most one millisecond's worth per write
  ASSERT_GT(step_n, 0.0);
  ASSERT_LT(step_n, safe->profile().peak_force_n) << "the jump below must exceed one step";
  ASSERT_TRUE(drive({}, [&] { return true; }));
  safe->write(rt::now_ns(), {0.0, -100.0, 0.0});
  const double sent = math::norm(safe->sent_force_n());
  EXPECT_LE(sent, step_n + 1e-9);
  EXPECT_GT(sent, 0.0);
  EXPECT_GT(safe->slew_limited(), 0u);
  // the device gets that limited force, not the jump
  ASSERT_TRUE(test::eventually([&] { return std::abs(math::norm(device_force_n()) - sent) < 1e-9; }, 1.0)) << math::norm(device_force_n());
}

TEST_P(VendorSafety, TheForceIsZeroWhenTheDeviceGoesAway) {
  ASSERT_TRUE(drive({0.5, 0.0, 0.0}, [&] { return std::abs(math::norm(device_force_n()) - 0.5) < 1e-9; }));
  safe->deactivate();
  EXPECT_EQ(math::norm(device_force_n()), 0.0);
  safe.reset();
  EXPECT_EQ(math::norm(device_force_n()), 0.0);
  EXPECT_TRUE(test::eventually([&] { return !device_open(); }, 1.0)) << "the device is closed (the connection to the service is gone)";
}

TEST_P(VendorSafety, TheLoopsReadAndWriteAllocateNothing) {
  ForceSample s;
  ASSERT_TRUE(test::eventually([&] { return safe->read(rt::now_ns(), s); }));
  test::AllocGuard guard;
  for (int i = 0; i < 1000; ++i) {
    safe->read(rt::now_ns(), s);
    safe->write(rt::now_ns(), {0.001 * i, 0.0, 0.0});
  }
  EXPECT_EQ(guard.allocations(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Backends, VendorSafety, ::testing::Values(on_fake<DhdForceDevice, DhdParams>("dhd", FAKE_DHD_LIBRARY), on_fake<HdForceDevice, HdParams>("hd", FAKE_HD_LIBRARY), on_emulated_service()), [](const auto& param_info) { return std::string(param_info.param.name); });

}  // namespace
}  // namespace enact::devices::vendor
