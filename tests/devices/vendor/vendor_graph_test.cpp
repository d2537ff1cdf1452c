// The vendor backends in a graph: wired from node params (core/node/components.cpp) inside
// the safety layer, with the params of other devices refused; and the co-located bridge
// started with the real `enact launch` for 10 s on each fake library (bridge_rt_dhd.yaml,
// bridge_rt_hd.yaml: the fake's hand walking the bridge path) and on the emulated Inverse
// Service (bridge_rt_inverse3_emulated.yaml: the emulator's scripted hand): the handle moves
// along the bridge in the enact frame, forces and pins follow contact.
//
// Machine assumptions: 2 noisy shared cores; only generous bounds on timing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ostream>
#include <string>

#include "core/devices/inverse3/emulated.h"
#include "core/devices/inverse3/emulator.h"
#include "core/devices/safety.h"
#include "core/devices/vendor/dhd_device.h"
#include "core/devices/vendor/hd_device.h"
#include "core/node/components.h"
#include "core/rt/clock.h"
#include "tests/devices/vendor/fake_library.h"
#include "tests/integration/integration_util.h"
#include "tests/cli/cli_support.h"
#include "tests/support/refusal.h"

namespace enact::test {
namespace {

constexpr double kReadyTimeout_s = 30.0;
constexpr double kObserve_s = 10.0;  // issue 29: each stand-in runs the bridge for 10 s
constexpr double kGraphDuration_s = 30.0;  // a safety net: the test stops the graph itself

TEST(VendorComponents, ADhdDeviceComesConfiguredInsideTheSafetyLayer) {
  FakeLibrary fake(FAKE_DHD_LIBRARY);
  fake.set_up();
  graph::Params p("ffd");
  p.set("device", "dhd");
  p.set("library", FAKE_DHD_LIBRARY);
  auto d = graph::make_force_device(p);
  p.refuse_unknown();
  auto* safe = dynamic_cast<devices::SafeForceDevice*>(d.get());
  ASSERT_NE(safe, nullptr);
  EXPECT_NE(dynamic_cast<devices::vendor::DhdForceDevice*>(&safe->inner()), nullptr);
  EXPECT_EQ(d->profile().name, "omega3");
}

TEST(VendorComponents, AnHdDeviceTakesItsProfileAndName) {
  FakeLibrary fake(FAKE_HD_LIBRARY);
  fake.set_up();
  graph::Params p("ffd");
  p.set("device", "hd");
  p.set("library", FAKE_HD_LIBRARY);
  p.set("device_name", "Default Device");
  p.set("profile", "falcon");
  auto d = graph::make_force_device(p);
  auto* safe = dynamic_cast<devices::SafeForceDevice*>(d.get());
  ASSERT_NE(safe, nullptr);
  EXPECT_NE(dynamic_cast<devices::vendor::HdForceDevice*>(&safe->inner()), nullptr);
  EXPECT_EQ(d->profile().name, "falcon");
}

TEST(VendorComponents, AnInverse3OnItsEmulatorComesConfigured) {
  graph::Params p("ffd");
  p.set("device", "inverse3");
  p.set("transport", "emulator");
  p.set("start_m", "0.01,0.02,0.0");
  auto d = graph::make_force_device(p);
  p.refuse_unknown();
  auto* safe = dynamic_cast<devices::SafeForceDevice*>(d.get());
  ASSERT_NE(safe, nullptr);
  ASSERT_NE(dynamic_cast<devices::inverse3::EmulatedInverse3*>(&safe->inner()), nullptr);
  EXPECT_EQ(d->profile().name, "inverse3");
  d->activate();
  devices::ForceSample s;
  ASSERT_TRUE(eventually([&] { return d->read(rt::now_ns(), s) && s.faults == 0; }, 5.0));
  EXPECT_NEAR(s.position_m.x, 0.01, 2e-4);
  EXPECT_NEAR(s.position_m.y, 0.02, 2e-4);
}

TEST(VendorComponents, ParamsOfOtherDevicesAreRefused) {
  const auto refusal = [](const std::string& device, const char* name, const char* value) {
    graph::Params p("ffd");
    p.set("device", device);
    p.set(name, value);
    return error_of([&] { graph::make_force_device(p); });
  };
  EXPECT_NE(refusal("dhd", "hand_path", "x.csv").find("parameter hand_path is only for device=simulated"), std::string::npos);
  EXPECT_NE(refusal("dhd", "device_name", "x").find("parameter device_name is only for device=hd"), std::string::npos);
  EXPECT_NE(refusal("hd", "serial", "x").find("parameter serial is only for device=falcon"), std::string::npos);
  EXPECT_NE(refusal("simulated", "library", "x").find("parameter library is only for device=dhd or device=hd"), std::string::npos);
  EXPECT_NE(refusal("dhd", "transport", "emulator").find("parameter transport is only for device=falcon or device=inverse3"), std::string::npos);
  EXPECT_NE(refusal("falcon", "origin_m", "0,0,0").find("parameter origin_m is only for device=inverse3"), std::string::npos);
  EXPECT_NE(refusal("inverse3", "hand_path", "x.csv").find("parameter hand_path is only for transport=emulator"), std::string::npos);
}

TEST(VendorCli, DevicesSaysWhatIsMissingForEachAbsentDevice) {
  int closed_port = 0;
  {
    devices::inverse3::Inverse3Emulator gone({});
    closed_port = gone.port();
  }
  const RunResult r = enact("devices --dhd-library /nonexistent/libdhd.so --hd-library /nonexistent/libHD.so --inverse3-port " + std::to_string(closed_port));
  EXPECT_NE(r.out.find("Force Dimension (device: dhd): absent: cannot load /nonexistent/libdhd.so"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fix: install the Force Dimension SDK"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("OpenHaptics (device: hd): absent: cannot load /nonexistent/libHD.so"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Haply Inverse3 (device: inverse3): absent: the Haply Inverse Service does not answer on 127.0.0.1:" + std::to_string(closed_port)),
            std::string::npos)
      << r.out;
  // this machine has no supported USB device either: nothing found
  if (r.out.find("no supported USB device found") != std::string::npos) {
    EXPECT_EQ(r.exit_code, 1) << r.out;
  }
}

TEST(VendorCli, DevicesFindsEachOnItsStandIn) {
  FakeLibrary dhd(FAKE_DHD_LIBRARY), hd(FAKE_HD_LIBRARY);
  dhd.set_up();
  hd.set_up();
  devices::inverse3::Inverse3Emulator emu({});
  const std::string port = std::to_string(emu.port());
  const RunResult r = enact(std::string("devices --dhd-library ") + FAKE_DHD_LIBRARY + " --hd-library " + FAKE_HD_LIBRARY + " --inverse3-port " + port);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find(std::string("Force Dimension (device: dhd): 1 device(s) found through ") + FAKE_DHD_LIBRARY + "  ready"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(std::string("OpenHaptics (device: hd): the default device opens through ") + FAKE_HD_LIBRARY + "  ready"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Haply Inverse3 (device: inverse3): 049D on the service at 127.0.0.1:" + port + "  ready"), std::string::npos) << r.out;
}

TEST(VendorCli, DevicesSaysAnInverse3IsInUse) {
  devices::inverse3::Inverse3EmulatorParams busy;
  busy.in_use = true;
  devices::inverse3::Inverse3Emulator emu(busy);
  const RunResult r = enact("devices --dhd-library /nonexistent/libdhd.so --hd-library /nonexistent/libHD.so --inverse3-port " + std::to_string(emu.port()));
  EXPECT_NE(r.out.find("049D on the service at 127.0.0.1:" + std::to_string(emu.port()) + "  in use by another session"), std::string::npos) << r.out;
}

struct Run {
  const char* device;
  const char* launch;
  std::vector<std::string> args;  // launch arguments
};

// a failing run names its device, not the parameter's bytes
void PrintTo(const Run& run, std::ostream* os) { *os << run.device; }

class VendorGraph : public ::testing::TestWithParam<Run> {};

TEST_P(VendorGraph, TheBridgeRunsOnItsStandIn) {
  TempDir dir;
  // a fake library's hand walks the bridge path (the child inherits the environment)
  setenv("ENACT_FAKE_HAND_PATH", source_path("launch/paths/bridge_walk.csv").c_str(), 1);
  Launcher launcher(dir, source_path(GetParam().launch), kGraphDuration_s, GetParam().args);
  unsetenv("ENACT_FAKE_HAND_PATH");
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  Observer obs(launcher.endpoint());
  obs.all_topics();
  Observed seen;
  obs.observe(kObserve_s, seen);
  ASSERT_GE(seen.states.size(), 1000u) << launcher.log();
  ASSERT_GE(seen.scenes.size(), 100u);

  // the handle follows the bridge path in the enact frame: it starts at the path's first
  // point (-6.0, -20.9, 13.0) mm and moves over the bridge (a wrong frame puts it elsewhere)
  const auto& p0 = seen.states.front().position();
  EXPECT_NEAR(p0.x(), -0.0060, 0.004);
  EXPECT_NEAR(p0.y(), -0.0209, 0.004);
  EXPECT_NEAR(p0.z(), 0.013, 0.004);
  double span = 0.0;
  std::uint64_t healthy = 0, late = 0;
  for (const auto& s : seen.states) {
    span = std::max(span, std::hypot(s.position().x() - p0.x(), s.position().y() - p0.y()));
    healthy += s.faults() == 0;
    late += s.faults() == msgs::DEVICE_FAULT_WATCHDOG;
  }
  std::printf("[ %s graph ] %zu device states, %llu without a fault, %llu cut by the loop's watchdog, the handle moved %.1f mm\n", GetParam().device,
              seen.states.size(), static_cast<unsigned long long>(healthy), static_cast<unsigned long long>(late), span * 1e3);
  EXPECT_GT(span, 0.01);
  // the device and its library healthy on most samples: the force cut by the loop's own
  // watchdog (a late tick on a busy machine) is not the device's doing
  EXPECT_GT((healthy + late) * 10, seen.states.size() * 9) << "most samples healthy";

  // forces and pins follow contact (CM1), and the handle rests on the top at times
  const ContactCheck contact = check_follows_contact(seen.scenes);
  std::printf("[ %s graph ] %zu scenes, %d on the top (%d of them re-synchronised, without force)\n", GetParam().device, seen.scenes.size(), contact.on_top, contact.resting);
  EXPECT_EQ(contact.bad, 0) << contact.first_bad;
  EXPECT_LE(static_cast<std::uint64_t>(contact.resting), seen.states.size() - healthy) << "on the top without force where no fault cut the force path";
  EXPECT_GT(contact.on_top - contact.resting, 10) << "the handle never rested on the top: the checks above were vacuous";
}

INSTANTIATE_TEST_SUITE_P(StandIns, VendorGraph,
                         ::testing::Values(Run{"dhd", "launch/bridge_rt_dhd.yaml", {std::string("library=") + FAKE_DHD_LIBRARY}},
                                           Run{"hd", "launch/bridge_rt_hd.yaml", {std::string("library=") + FAKE_HD_LIBRARY}},
                                           Run{"inverse3", "launch/bridge_rt_inverse3_emulated.yaml", {}}),
                         [](const auto& param_info) { return std::string(param_info.param.device); });

}  // namespace
}  // namespace enact::test
