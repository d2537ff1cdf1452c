// The USB layer's device search and its messages (on a fake bus: absent, serials, permission
// denied with the udev fix, busy), the report of `enact devices`, the shipped udev rules,
// the fake transport's cable (unplug, stall), and the real libusb bus of this machine.
#include "core/devices/usb/transport.h"

#include <gtest/gtest.h>

#include <string>

#include "core/config/yaml.h"
#include "core/devices/usb/libusb.h"
#include "tests/devices/usb_test_util.h"
#include "tests/support/test_util.h"

namespace enact::devices::usb {
namespace {

// an emulator that answers every transfer with `bytes` of success
class Echo final : public Emulator {
 public:
  Outcome control(const ControlSetup&, std::uint8_t*, std::uint16_t length) override { return {Status::ok, length}; }
  Outcome out(std::uint8_t, const std::uint8_t*, int length) override { return {Status::ok, length}; }
  Outcome in(std::uint8_t, std::uint8_t*, int length) override { return {Status::ok, length}; }
};

FakeDevice falcon(const std::string& serial, int address, Status open_status = Status::ok) {
  FakeDevice d = emulated_device("falcon", std::make_shared<Echo>());
  d.found.serial = serial;
  d.found.address = address;
  d.found.path = "/dev/bus/usb/001/00" + std::to_string(address);
  d.open_status = open_status;
  return d;
}

std::string open_error(Bus& bus, const std::string& backend, const std::string& serial) {
  return test::error_of([&] { open_device(bus, backend, serial, {}); });
}

TEST(UsbTransport, TheSupportedDevicesAreTheFalconAndTheMetecCells) {
  EXPECT_EQ(usb_id(supported("falcon").vendor, supported("falcon").product), "0403:cb48");
  EXPECT_EQ(usb_id(supported("metec").vendor, supported("metec").product), "0452:0100");
  EXPECT_THROW(supported("phantom"), std::invalid_argument);
}

TEST(UsbTransport, OpenPicksTheDeviceWithTheSerialAndClaimsTheInterface) {
  FakeBus bus({falcon("A1", 2), falcon("B2", 3)});
  EXPECT_NE(open_device(bus, "falcon", "B2", {1, 0}), nullptr);
  EXPECT_NE(open_device(bus, "falcon", "", {-1, 0}), nullptr);
  ASSERT_EQ(bus.claims().size(), 2u);
  EXPECT_EQ(bus.claims()[0].configuration, 1);
  const std::string error = open_error(bus, "falcon", "C3");
  EXPECT_NE(error.find("no Novint Falcon (USB 0403:cb48) with serial 'C3' (found: A1, B2)"), std::string::npos) << error;
}

TEST(UsbTransport, AnAbsentDeviceSaysSoAndPointsToTheEmulator) {
  FakeBus bus({falcon("A1", 2)});
  const std::string error = open_error(bus, "metec", "");
  EXPECT_NE(error.find("no Metec Braille cells (USB 0452:0100) found on the USB bus"), std::string::npos) << error;
  EXPECT_NE(error.find("fix: plug it in"), std::string::npos) << error;
  EXPECT_NE(error.find("transport=emulator"), std::string::npos) << error;
}

TEST(UsbTransport, PermissionDeniedGivesTheUdevRuleToInstall) {
  FakeBus bus({falcon("A1", 4, Status::access)});
  const std::string error = open_error(bus, "falcon", "");
  EXPECT_NE(error.find("permission denied opening the Novint Falcon (USB 0403:cb48) at /dev/bus/usb/001/004"), std::string::npos) << error;
  EXPECT_NE(error.find("fix: install enact's udev rules"), std::string::npos) << error;
  EXPECT_NE(error.find(udev_rules()), std::string::npos) << error;
}

TEST(UsbTransport, TheShippedUdevRulesAreWhatEnactPrints) {
  EXPECT_EQ(test::read_file(test::source_path("scripts/udev/99-enact.rules")), udev_rules());
  // one rule per supported device, by vendor and product, for the logged-in user
  for (const auto& d : supported_devices()) {
    const std::string id = usb_id(d.vendor, d.product);
    const std::string rule = "ATTRS{idVendor}==\"" + id.substr(0, 4) + "\", ATTRS{idProduct}==\"" + id.substr(5) + "\"";
    EXPECT_NE(udev_rules().find(rule), std::string::npos) << rule;
  }
  EXPECT_NE(udev_rules().find("TAG+=\"uaccess\""), std::string::npos);
}

TEST(UsbTransport, TheReportListsDevicesOrSaysNoneWasFound) {
  const std::string none = report({});
  EXPECT_NE(none.find("no supported USB device found"), std::string::npos) << none;
  EXPECT_NE(none.find("0403:cb48  Novint Falcon (device: falcon)"), std::string::npos) << none;
  EXPECT_NE(none.find("0452:0100  Metec Braille cells (device: metec)"), std::string::npos) << none;

  FakeDevice ok = falcon("FT1", 2);
  FakeDevice denied = emulated_device("metec", std::make_shared<Echo>());
  denied.found.access = Status::access;
  denied.found.serial = "";
  const std::string two = report({ok.found, denied.found});
  EXPECT_NE(two.find("0403:cb48  Novint Falcon"), std::string::npos) << two;
  EXPECT_NE(two.find("serial FT1"), std::string::npos) << two;
  EXPECT_NE(two.find("device: falcon   ready"), std::string::npos) << two;
  EXPECT_NE(two.find("device: metec    permission denied"), std::string::npos) << two;
  EXPECT_NE(two.find(udev_rules()), std::string::npos) << "the rules to install" << two;
  EXPECT_EQ(report({ok.found}).find("udev"), std::string::npos) << "no fix when nothing is wrong";
}

TEST(UsbTransport, TheFakeCableUnplugsAndStalls) {
  auto cable = std::make_shared<FakeCable>();
  FakeTransport t(std::make_shared<Echo>(), cable);
  std::uint8_t buf[8] = {};
  EXPECT_EQ(t.bulk(0x81, buf, 8, 10).status, Status::ok);
  cable->stalled = true;
  const Outcome stalled = t.control({}, buf, 8, 5);
  EXPECT_EQ(stalled.status, Status::timeout);
  EXPECT_EQ(stalled.bytes, 0);
  cable->stalled = false;
  cable->unplugged = true;
  EXPECT_EQ(t.bulk(0x02, buf, 8, 10).status, Status::no_device);
  EXPECT_EQ(t.interrupt(0x81, buf, 8, 10).status, Status::no_device);
  EXPECT_FALSE(t.emergency_bulk_out(0x02, buf, 8));
  EXPECT_EQ(cable->transfers.load(), 4u);
}

TEST(UsbLibusb, ThisMachinesBusListsWithoutFailing) {
  // the real libusb: whatever this machine has, listing works and every device it reports
  // is a supported one with a device file
  LibusbBus bus;
  for (const Found& f : bus.list()) {
    EXPECT_NO_THROW(supported(f.vendor == 0x0403 ? "falcon" : "metec"));
    EXPECT_EQ(f.path.rfind("/dev/bus/usb/", 0), 0u) << f.path;
  }
  EXPECT_EQ(status_of(-7 /* LIBUSB_ERROR_TIMEOUT */), Status::timeout);
  EXPECT_EQ(status_of(-4 /* LIBUSB_ERROR_NO_DEVICE */), Status::no_device);
  EXPECT_EQ(status_of(-3 /* LIBUSB_ERROR_ACCESS */), Status::access);
}

TEST(UsbLibusb, EnactDevicesOnThisMachineSaysNoneFound) {
  LibusbBus bus;
  if (!bus.list().empty()) GTEST_SKIP() << "this machine has a supported device plugged in";
  const test::RunResult r = test::run(std::string(ENACT_CLI) + " devices");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("no supported USB device found"), std::string::npos) << r.out << r.err;
  EXPECT_NE(r.out.find("0403:cb48  Novint Falcon (device: falcon)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("transport=emulator"), std::string::npos) << r.out;
  // and the rules, as shipped
  const test::RunResult rules = test::run(std::string(ENACT_CLI) + " devices --udev-rules");
  EXPECT_EQ(rules.exit_code, 0);
  EXPECT_EQ(rules.out, udev_rules());
}

}  // namespace
}  // namespace enact::devices::usb
