// The Force Dimension backend (core/devices/vendor/dhd_device.h) against the fake libdhd
// (fake_dhd.cpp): the frame and units both ways, one polling thread (never the loop's),
// buttons, refusals that name the file, the function and the fix, a failing device, the
// backend's own zeroing (a silent loop, deactivate, destruction).
#include <gtest/gtest.h>

#include <dlfcn.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "core/devices/vendor/dhd_device.h"
#include "core/rt/clock.h"
#include "tests/devices/vendor/fake_library.h"
#include "tests/support/refusal.h"

namespace enact::devices::vendor {
namespace {

using math::Vec3;

class Dhd : public ::testing::Test {
 protected:
  void SetUp() override { fake.set_up(); }
  // a configured, active backend on the fake
  std::unique_ptr<DhdForceDevice> open_device() {
    DhdParams p;
    p.library = FAKE_DHD_LIBRARY;
    auto d = std::make_unique<DhdForceDevice>(p);
    d->configure();
    d->activate();
    return d;
  }
  // the backend's sample, once it is within tol_m of `where` (enact frame); false if never
  bool settles_at(DhdForceDevice& d, const Vec3& where, ForceSample& s, double tol_m = 2e-4) {
    return test::eventually([&] { return d.read(rt::now_ns(), s) && math::norm(s.position_m - where) < tol_m; }, 5.0);
  }
  test::FakeLibrary fake{FAKE_DHD_LIBRARY};
};

TEST_F(Dhd, ReadsThePositionInTheEnactFrame) {
  auto d = open_device();
  // DHD: x at the operator, y to the right, z up; enact: x right, y away, z up
  fake.hold({0.02, 0.01, 0.03});
  ForceSample s;
  ASSERT_TRUE(settles_at(*d, {0.01, -0.02, 0.03}, s)) << s.position_m.x << " " << s.position_m.y << " " << s.position_m.z;
  EXPECT_EQ(s.faults, 0u);
  EXPECT_EQ(d->profile().name, "omega3");
}

TEST_F(Dhd, ReportsTheVelocityInTheEnactFrame) {
  auto d = open_device();
  // the hand pulls the handle towards the operator (DHD +x): enact -y
  fake.hold({0.04, 0.0, 0.0});
  ForceSample s;
  ASSERT_TRUE(test::eventually([&] { return d->read(rt::now_ns(), s) && s.velocity_m_per_s.y < -0.05; }, 2.0)) << s.velocity_m_per_s.y;
  EXPECT_LT(std::abs(s.velocity_m_per_s.x), 0.01);
}

TEST_F(Dhd, CommandsTheForceInTheDhdFrame) {
  auto d = open_device();
  // enact +x (right) is DHD +y; enact +y (away) is DHD -x; z is z
  const std::pair<Vec3, Vec3> cases[] = {{{1.0, 0, 0}, {0, 1.0, 0}}, {{0, 2.0, 0}, {-2.0, 0, 0}}, {{0, 0, -3.0}, {0, 0, -3.0}}};
  for (const auto& [enact_n, dhd_n] : cases) {
    ASSERT_TRUE(test::eventually([&, enact_n = enact_n, dhd_n = dhd_n] {
      d->write(rt::now_ns(), enact_n);
      return math::norm(fake.force_n() - dhd_n) < 1e-12;
    })) << "sent " << fake.force_n().x << " " << fake.force_n().y << " " << fake.force_n().z;
  }
}

TEST_F(Dhd, AForceMovesTheHandleItsWay) {
  auto d = open_device();
  // 1 N to the right against the fake hand's 200 N/m: 5 mm to the right, in the enact frame
  ForceSample s;
  ASSERT_TRUE(test::eventually([&] {
    d->write(rt::now_ns(), {1.0, 0.0, 0.0});
    return d->read(rt::now_ns(), s) && std::abs(s.position_m.x - 0.005) < 2e-4 && std::abs(s.velocity_m_per_s.x) < 1e-3;
  }, 5.0)) << s.position_m.x;
  EXPECT_NEAR(s.position_m.y, 0.0, 2e-4);
}

TEST_F(Dhd, TheDeviceIsPolledFromOneThreadNeverTheLoops) {
  auto d = open_device();
  void* lib = dlopen(FAKE_DHD_LIBRARY, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(lib, nullptr);
  auto callers = reinterpret_cast<int (*)()>(dlsym(lib, "fake_callers"));
  ASSERT_NE(callers, nullptr);
  // this thread is the loop: its reads and writes must not reach the device
  ForceSample s;
  for (int i = 0; i < 200; ++i) {
    d->read(rt::now_ns(), s);
    d->write(rt::now_ns(), {0.01 * i, 0.0, 0.0});
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  EXPECT_EQ(callers(), 1) << "the device was called from more than one thread";
  dlclose(lib);
}

TEST_F(Dhd, ButtonsReachTheSample) {
  auto d = open_device();
  fake.set_buttons(0b101);
  ForceSample s;
  ASSERT_TRUE(test::eventually([&] { return d->read(rt::now_ns(), s) && s.buttons == 0b101u; }));
}

TEST_F(Dhd, AMissingLibraryIsRefusedNamingTheFileAndTheFix) {
  DhdParams p;
  p.library = "/nonexistent/libdhd.so";
  DhdForceDevice d(p);
  const std::string e = test::error_of([&] { d.configure(); });
  EXPECT_NE(e.find("cannot load /nonexistent/libdhd.so"), std::string::npos) << e;
  EXPECT_NE(e.find("fix: install the Force Dimension SDK"), std::string::npos) << e;
}

TEST_F(Dhd, ALibraryWithoutTheDhdFunctionsIsRefusedNamingTheFunction) {
  DhdParams p;
  p.library = FAKE_HD_LIBRARY;
  DhdForceDevice d(p);
  const std::string e = test::error_of([&] { d.configure(); });
  EXPECT_NE(e.find("has no function dhdOpen"), std::string::npos) << e;
}

TEST_F(Dhd, NoDeviceIsRefusedWithTheSdkReason) {
  fake.set_present(0);
  DhdParams p;
  p.library = FAKE_DHD_LIBRARY;
  DhdForceDevice d(p);
  const std::string e = test::error_of([&] { d.configure(); });
  EXPECT_NE(e.find("no Force Dimension device could be opened (no device found)"), std::string::npos) << e;
  EXPECT_NE(e.find("udev"), std::string::npos) << e;
}

TEST_F(Dhd, AnUncalibratedDeviceIsRefusedAndClosed) {
  fake.set_calibrated(0);
  DhdParams p;
  p.library = FAKE_DHD_LIBRARY;
  DhdForceDevice d(p);
  const std::string e = test::error_of([&] { d.configure(); });
  EXPECT_NE(e.find("not calibrated"), std::string::npos) << e;
  EXPECT_NE(e.find("fix: calibrate it"), std::string::npos) << e;
  EXPECT_EQ(fake.is_open(), 0);
}

TEST_F(Dhd, AFailingDeviceIsADeviceError) {
  auto d = open_device();
  ForceSample s;
  ASSERT_TRUE(d->read(rt::now_ns(), s) || test::eventually([&] { return d->read(rt::now_ns(), s); }));
  fake.set_failing(1);
  ASSERT_TRUE(test::eventually([&] { return !d->read(rt::now_ns(), s); }, 1.0));
  EXPECT_TRUE(has(s.faults, DeviceFault::device_error));
}

TEST_F(Dhd, ASilentLoopGetsZeroForceFromTheBackend) {
  auto d = open_device();
  ASSERT_TRUE(test::eventually([&] {
    d->write(rt::now_ns(), {1.0, 0, 0});
    return fake.force_n().y == 1.0;
  }));
  // no more writes: within the command timeout (20 ms) and a margin, zero
  EXPECT_TRUE(test::eventually([&] { return math::norm(fake.force_n()) == 0.0; }, 1.0));
}

TEST_F(Dhd, DeactivateAndDestructionZeroTheForceAndClose) {
  auto d = open_device();
  ASSERT_TRUE(test::eventually([&] {
    d->write(rt::now_ns(), {0, 0, 2.0});
    return fake.force_n().z == 2.0;
  }));
  d->deactivate();
  EXPECT_EQ(math::norm(fake.force_n()), 0.0);
  ForceSample s;
  EXPECT_FALSE(d->read(rt::now_ns(), s));
  d.reset();
  EXPECT_EQ(fake.is_open(), 0);
}

}  // namespace
}  // namespace enact::devices::vendor
