// The wiring of the USB backends into a graph's components (core/node/components.cpp):
// device falcon and device metec on their emulators from node params, the Falcon inside the
// safety layer, and params that do not belong to the chosen device or transport refused.
#include <gtest/gtest.h>

#include <string>

#include "core/config/yaml.h"
#include "core/devices/falcon/falcon_device.h"
#include "core/devices/metec/metec_device.h"
#include "core/devices/safety.h"
#include "core/node/components.h"
#include "core/rt/clock.h"
#include "tests/devices/usb_test_util.h"
#include "tests/support/test_util.h"

namespace enact::graph {
namespace {

TEST(UsbComponents, AnEmulatedFalconComesConfiguredInsideTheSafetyLayer) {
  Params p("ffd");
  p.set("device", "falcon");
  p.set("transport", "emulator");
  p.set("start_m", "0.01,0,0.012");
  p.set("max_force_n", "5");
  auto d = make_force_device(p);
  p.refuse_unknown();
  auto* safe = dynamic_cast<devices::SafeForceDevice*>(d.get());
  ASSERT_NE(safe, nullptr);
  EXPECT_EQ(d->profile().name, "falcon");
  EXPECT_EQ(d->profile().peak_force_n, 5.0);
  d->activate();
  // the emulated grip where the hand holds it, read through the backend
  devices::ForceSample s;
  ASSERT_TRUE(test::eventually([&] { return d->read(rt::now_ns(), s) && s.faults == 0; }));
  EXPECT_NEAR(s.position_m.x, 0.01, 2e-4);
  EXPECT_NEAR(s.position_m.z, 0.012, 2e-4);
  // the safety layer on top: a command over the limit is clamped and said so
  d->write(rt::now_ns(), {0, 0, 9});
  d->read(rt::now_ns(), s);
  EXPECT_TRUE(devices::has(s.faults, devices::DeviceFault::clamped));
  d->deactivate();
}

TEST(UsbComponents, AnEmulatedFalconUploadsTheFirmwareItIsGiven) {
  test::TempDir dir;
  test::write_file(dir.file("fw.bin"), std::string(150, 'x'));
  Params p("ffd");
  p.set("device", "falcon");
  p.set("transport", "emulator");
  p.set("firmware", dir.file("fw.bin"));
  auto d = make_force_device(p);
  auto* safe = dynamic_cast<devices::SafeForceDevice*>(d.get());
  ASSERT_NE(safe, nullptr);
  auto* falcon = dynamic_cast<devices::falcon::FalconForceDevice*>(&safe->inner());
  ASSERT_NE(falcon, nullptr);
  EXPECT_TRUE(falcon->uploaded_firmware());
}

TEST(UsbComponents, AnEmulatedMetecDisplayComesConfigured) {
  Params p("tactile");
  p.set("device", "metec");
  p.set("transport", "emulator");
  p.set("rows", "4");
  p.set("cols", "8");
  p.set("first_cell", "4");
  auto d = make_tactile_device(p);
  p.refuse_unknown();
  EXPECT_EQ(d->rows(), 4);
  EXPECT_EQ(d->cols(), 8);
  auto* metec = dynamic_cast<devices::metec::MetecTactileDevice*>(d.get());
  ASSERT_NE(metec, nullptr);
  EXPECT_EQ(metec->display_cells(), 16);
  d->activate();
  d->write(rt::now_ns(), 0xFFFFFFFFu);
  ASSERT_TRUE(test::eventually([&] { return metec->module_writes() >= 2; }));
  d->deactivate();
}

TEST(UsbComponents, ParamsOfAnotherDeviceOrTransportAreRefused) {
  Params hand("ffd");
  hand.set("device", "falcon");
  hand.set("hand_path", "x.csv");
  EXPECT_NE(test::error_of([&] { make_force_device(hand); }).find("hand_path is only for transport=emulator"), std::string::npos);

  Params profile("ffd");
  profile.set("device", "falcon");
  profile.set("transport", "emulator");
  profile.set("profile", "ergos");
  EXPECT_NE(test::error_of([&] { make_force_device(profile); }).find("profile is only for device=simulated"), std::string::npos);

  Params simulated("ffd");
  simulated.set("firmware", "fw.bin");
  EXPECT_NE(test::error_of([&] { make_force_device(simulated); }).find("firmware is only for device=falcon"), std::string::npos);

  Params cells("tactile");
  cells.set("first_cell", "3");
  EXPECT_NE(test::error_of([&] { make_tactile_device(cells); }).find("first_cell is only for device=metec"), std::string::npos);

  Params transport("tactile");
  transport.set("device", "metec");
  transport.set("transport", "serial");
  EXPECT_NE(test::error_of([&] { make_tactile_device(transport); }).find("must be one of usb, emulator"), std::string::npos);

  Params unknown("ffd");
  unknown.set("device", "phantom");
  EXPECT_NE(test::error_of([&] { make_force_device(unknown); }).find("must be one of simulated, falcon"), std::string::npos);
}

}  // namespace
}  // namespace enact::graph
