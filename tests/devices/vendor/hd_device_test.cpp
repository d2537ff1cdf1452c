// The OpenHaptics backend (core/devices/vendor/hd_device.h) against the fake libHD
// (fake_hd.cpp, whose scheduler calls our servo callback every millisecond): millimetres to
// metres and the frame both ways, device state touched only in the servo loop, buttons,
// refusals, an HD error in the servo loop, and the scheduler stopped and the device disabled
// on destruction.
#include <gtest/gtest.h>

#include <dlfcn.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "core/devices/vendor/hd_device.h"
#include "core/rt/clock.h"
#include "tests/devices/vendor/fake_library.h"
#include "tests/support/refusal.h"

namespace enact::devices::vendor {
namespace {

using math::Vec3;

HdParams fake_params() {
  HdParams p;
  p.library = FAKE_HD_LIBRARY;
  return p;
}

class Hd : public ::testing::Test {
 protected:
  void SetUp() override { fake.set_up(); }
  test::FakeLibrary fake{FAKE_HD_LIBRARY};
};

TEST_F(Hd, ReadsMillimetresAsMetresInTheEnactFrame) {
  HdForceDevice d(fake_params());
  d.configure();
  d.activate();
  // HD: x right, y up, z towards the user, in mm; enact: x right, y away, z up, in m
  fake.hold({0.01, 0.02, 0.03});
  ForceSample s;
  ASSERT_TRUE(test::eventually([&] { return d.read(rt::now_ns(), s) && math::norm(s.position_m - Vec3{0.01, -0.03, 0.02}) < 2e-4; }, 5.0))
      << s.position_m.x << " " << s.position_m.y << " " << s.position_m.z;
  EXPECT_EQ(s.faults, 0u);
  EXPECT_GT(d.servo_ticks(), 0u);
  EXPECT_EQ(d.profile().name, "touch");
  // moving: the velocity in m/s, not mm/s (the hand pulls the handle up: enact +z)
  fake.hold({0.01, 0.05, 0.03});
  ASSERT_TRUE(test::eventually([&] { return d.read(rt::now_ns(), s) && s.velocity_m_per_s.z > 0.05; }, 2.0));
  EXPECT_LT(s.velocity_m_per_s.z, 5.0) << "a velocity in mm/s";
}

TEST_F(Hd, SetsTheForceInTheHdFrameAndItMovesTheHandle) {
  HdForceDevice d(fake_params());
  d.configure();
  d.activate();
  // enact +y (away from the user) is HD -z
  ASSERT_TRUE(test::eventually([&] {
    d.write(rt::now_ns(), {0.0, 0.5, 0.0});
    return math::norm(fake.force_n() - Vec3{0.0, 0.0, -0.5}) < 1e-12;
  }));
  // 0.5 N against the fake hand's 200 N/m: 2.5 mm away from the user
  ForceSample s;
  ASSERT_TRUE(test::eventually([&] {
    d.write(rt::now_ns(), {0.0, 0.5, 0.0});
    return d.read(rt::now_ns(), s) && std::abs(s.position_m.y - 0.0025) < 1e-4 && std::abs(s.velocity_m_per_s.y) < 1e-3;
  }, 5.0)) << s.position_m.y;
  // enact +z (up) is HD +y
  ASSERT_TRUE(test::eventually([&] {
    d.write(rt::now_ns(), {0.0, 0.0, 1.5});
    return math::norm(fake.force_n() - Vec3{0.0, 1.5, 0.0}) < 1e-12;
  }));
}

TEST_F(Hd, DeviceStateIsTouchedOnlyInTheServoLoop) {
  void* lib = dlopen(FAKE_HD_LIBRARY, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(lib, nullptr);
  auto off_servo = reinterpret_cast<int (*)()>(dlsym(lib, "fake_frame_calls_off_servo"));
  ASSERT_NE(off_servo, nullptr);
  const int before = off_servo();
  HdForceDevice d(fake_params());
  d.configure();
  d.activate();
  // this thread is the loop: frames and state calls belong to HD's servo thread
  ForceSample s;
  for (int i = 0; i < 200; ++i) {
    d.read(rt::now_ns(), s);
    d.write(rt::now_ns(), {0.0, 0.0, 0.001 * i});
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  EXPECT_GT(d.servo_ticks(), 0u);
  EXPECT_EQ(off_servo(), before) << "a frame or state call outside the servo loop";
  dlclose(lib);
}

TEST_F(Hd, TheStylusButtonsReachTheSample) {
  HdForceDevice d(fake_params());
  d.configure();
  d.activate();
  fake.set_buttons(0b10);
  ForceSample s;
  ASSERT_TRUE(test::eventually([&] { return d.read(rt::now_ns(), s) && s.buttons == 0b10u; }));
}

TEST_F(Hd, RefusalsNameTheProblemAndTheFix) {
  {
    HdParams p;
    p.library = "/nonexistent/libHD.so";
    HdForceDevice d(p);
    const std::string e = test::error_of([&] { d.configure(); });
    EXPECT_NE(e.find("cannot load /nonexistent/libHD.so"), std::string::npos) << e;
    EXPECT_NE(e.find("fix: install OpenHaptics"), std::string::npos) << e;
  }
  {
    HdParams p = fake_params();
    p.device_name = "Left Touch";
    HdForceDevice d(p);
    const std::string e = test::error_of([&] { d.configure(); });
    EXPECT_NE(e.find("cannot open the device 'Left Touch': communication error (fake)"), std::string::npos) << e;
    EXPECT_NE(e.find("Touch Setup"), std::string::npos) << e;
  }
  fake.set_calibrated(0);
  HdForceDevice d(fake_params());
  const std::string e = test::error_of([&] { d.configure(); });
  EXPECT_NE(e.find("the device is not calibrated"), std::string::npos) << e;
  EXPECT_NE(e.find("inkwell"), std::string::npos) << e;
  EXPECT_EQ(fake.is_open(), 0) << "a refused device is disabled again";
}

TEST_F(Hd, AnHdErrorInTheServoLoopIsADeviceError) {
  HdForceDevice d(fake_params());
  d.configure();
  d.activate();
  ForceSample s;
  ASSERT_TRUE(test::eventually([&] { return d.read(rt::now_ns(), s); }));
  fake.set_failing(1);
  ASSERT_TRUE(test::eventually([&] { return !d.read(rt::now_ns(), s); }, 1.0));
  EXPECT_TRUE(has(s.faults, DeviceFault::device_error));
}

TEST_F(Hd, DestructionStopsTheSchedulerAndDisablesTheDevice) {
  void* lib = dlopen(FAKE_HD_LIBRARY, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(lib, nullptr);
  auto running = reinterpret_cast<int (*)()>(dlsym(lib, "fake_scheduler_running"));
  ASSERT_NE(running, nullptr);
  {
    HdForceDevice d(fake_params());
    d.configure();
    d.activate();
    ASSERT_TRUE(test::eventually([&] {
      d.write(rt::now_ns(), {1.0, 0.0, 0.0});
      return fake.force_n().x == 1.0;
    }));
    EXPECT_EQ(running(), 1);
    d.deactivate();
    EXPECT_EQ(math::norm(fake.force_n()), 0.0) << "deactivate waits for a zero force to go out";
  }
  EXPECT_EQ(running(), 0);
  EXPECT_EQ(fake.is_open(), 0);
  dlclose(lib);
}

}  // namespace
}  // namespace enact::devices::vendor
