// The Metec backend against its emulator, in real time (its I/O thread runs): the pins reach
// the cells through the mapping, only changed modules are rewritten, shown() is what the
// cells physically show (the emulator's dots, rate limited), high voltage off with the pins
// lowered on deactivate, on a fault and on unplug, the emergency stop, configure's errors,
// and no allocation on the real-time side.
#include "core/devices/metec/metec_device.h"

#include <gtest/gtest.h>

#include <array>
#include <string>

#include "core/config/yaml.h"
#include "core/devices/metec/emulator.h"
#include "core/rt/clock.h"
#include "tests/devices/usb_test_util.h"
#include "tests/support/alloc_guard.h"

namespace enact::devices::metec {
namespace {

using test::eventually;

constexpr std::int64_t kMs = 1'000'000;

struct Rig {
  test::OnBus<MetecEmulator> on;
  MetecTactileDevice device;
  explicit Rig(MetecParams p = {}, usb::Status open_status = usb::Status::ok)
      : on("metec", std::make_shared<MetecEmulator>(), open_status), device(p, std::move(on.bus)) {}
};

// the message of configure()'s refusal
std::string configure_error(MetecTactileDevice& d) { return test::error_of([&] { d.configure(); }); }

std::array<float, 32> shown(MetecTactileDevice& d, std::int64_t now_ns) {
  std::array<float, 32> levels{};
  d.shown(now_ns, levels.data(), 32);
  return levels;
}

// what the emulated dots under each pin physically show at now_ns
std::array<double, 32> dots(const MetecEmulator& e, const Layout& l, std::int64_t now_ns) {
  std::array<double, 32> out{};
  for (int pin = 0; pin < l.pins(); ++pin) {
    const CellDot cd = cell_dot(l, pin);
    out[static_cast<std::size_t>(pin)] = e.dot_level(cd.cell, cd.dot, now_ns);
  }
  return out;
}

TEST(MetecDevice, ConfigureReadsTheDisplayAndActivateSwitchesTheHighVoltageOnWithPinsDown) {
  Rig rig;
  rig.device.configure();
  EXPECT_EQ(rig.device.identity(), "enact Metec emulator");
  EXPECT_EQ(rig.device.display_cells(), 16);
  EXPECT_FALSE(rig.on.emulator->high_voltage()) << "off until activate";
  rig.device.activate();
  EXPECT_TRUE(rig.on.emulator->high_voltage());
  EXPECT_EQ(rig.on.emulator->cell(0), 0);
  EXPECT_EQ(rig.on.emulator->cell(1), 0);
  EXPECT_EQ(rig.on.emulator->module_writes(0), 1u);
}

TEST(MetecDevice, PinsReachTheCellsAndShownIsWhatTheCellsPhysicallyShow) {
  Rig rig;
  const Layout l{4, 4, 0};
  rig.device.configure();
  rig.device.activate();
  // the left pin column and pin 15
  const std::uint32_t pins = 0x1111 | (1u << 15);
  rig.device.write(rt::now_ns(), pins);
  ASSERT_TRUE(eventually([&] { return rig.on.emulator->cell(1) == 0x01; }));
  EXPECT_EQ(rig.on.emulator->cell(0), 0xE2);
  // right after the write, mid-stroke, and after the rise time: the backend's model of the
  // cells and the emulated dots agree (both start when the display takes the write)
  for (std::int64_t later : {0 * kMs, 6 * kMs, 12 * kMs, 30 * kMs}) {
    const std::int64_t t = rt::now_ns() + later;
    const auto model = shown(rig.device, t);
    const auto physical = dots(*rig.on.emulator, l, t);
    for (int pin = 0; pin < 16; ++pin) EXPECT_NEAR(model[static_cast<std::size_t>(pin)], physical[static_cast<std::size_t>(pin)], 0.05) << "pin " << pin << " at +" << later / kMs << " ms";
  }
  // and after the rise time they are up, exactly those
  const auto up = shown(rig.device, rt::now_ns() + 30 * kMs);
  for (int pin = 0; pin < 16; ++pin) EXPECT_EQ(up[static_cast<std::size_t>(pin)], ((pins >> pin) & 1u) ? 1.0f : 0.0f) << pin;
  // rate limited like the cells: not up before the rise time is out
  const std::int64_t t0 = rt::now_ns();
  rig.device.write(t0, 1u << 5);
  ASSERT_TRUE(eventually([&] { return rig.on.emulator->cell(0) == 0x08; }));
  EXPECT_LT(rig.on.emulator->dot_level(0, 5, rt::now_ns() + 10 * kMs), 0.9);
  EXPECT_LT(shown(rig.device, rt::now_ns() + 10 * kMs)[5], 0.9f);
}

TEST(MetecDevice, OnlyChangedModulesAreRewritten) {
  // cells 7 and 8: the pin array straddles modules 0 and 1
  MetecParams p;
  p.first_cell = 7;
  Rig rig(p);
  rig.device.configure();
  rig.device.activate();
  const std::uint64_t m0 = rig.on.emulator->module_writes(0), m1 = rig.on.emulator->module_writes(1);
  // pins of columns 2-3 only: cell 8, module 1
  rig.device.write(rt::now_ns(), 1u << 2);
  ASSERT_TRUE(eventually([&] { return rig.on.emulator->cell(8) == 0x80; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(10));  // many I/O periods with nothing new
  EXPECT_EQ(rig.on.emulator->module_writes(0), m0);
  EXPECT_EQ(rig.on.emulator->module_writes(1), m1 + 1);
  // pins of column 0: cell 7, module 0 only
  rig.device.write(rt::now_ns(), (1u << 2) | 1u);
  ASSERT_TRUE(eventually([&] { return rig.on.emulator->cell(7) == 0x80; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(rig.on.emulator->module_writes(0), m0 + 1);
  EXPECT_EQ(rig.on.emulator->module_writes(1), m1 + 1);
  // the other cells of the modules stay blank
  for (int c : {0, 6, 9, 15}) EXPECT_EQ(rig.on.emulator->cell(c), 0) << c;
}

TEST(MetecDevice, DeactivateLowersThePinsAndSwitchesTheHighVoltageOff) {
  Rig rig;
  rig.device.configure();
  rig.device.activate();
  rig.device.write(rt::now_ns(), 0xFFFF);
  ASSERT_TRUE(eventually([&] { return rig.on.emulator->cell(0) == 0xFF; }));
  rig.device.deactivate();
  EXPECT_FALSE(rig.on.emulator->high_voltage());
  EXPECT_EQ(rig.on.emulator->cell(0), 0);
  EXPECT_EQ(rig.on.emulator->cell(1), 0);
  // everything down a rise time later, in the cells and in shown()
  const std::int64_t t = rt::now_ns() + 30 * kMs;
  const auto levels = shown(rig.device, t);
  const auto physical = dots(*rig.on.emulator, {4, 4, 0}, t);
  for (int pin = 0; pin < 16; ++pin) {
    EXPECT_EQ(levels[static_cast<std::size_t>(pin)], 0.0f) << pin;
    EXPECT_EQ(physical[static_cast<std::size_t>(pin)], 0.0) << pin;
  }
}

TEST(MetecDevice, ADisplayThatStopsAnsweringFaultsAndItsPinsAreShownFalling) {
  Rig rig;
  rig.device.configure();
  rig.device.activate();
  rig.device.write(rt::now_ns(), 0x000F);
  ASSERT_TRUE(eventually([&] { return rig.on.emulator->cell(1) != 0; }));
  rig.on.cable->stalled = true;
  rig.device.write(rt::now_ns(), 0x00F0);
  ASSERT_TRUE(eventually([&] { return rig.device.faulted(); }));
  EXPECT_FALSE(rig.device.unplugged());
  const auto levels = shown(rig.device, rt::now_ns() + 30 * kMs);
  for (int pin = 0; pin < 16; ++pin) EXPECT_EQ(levels[static_cast<std::size_t>(pin)], 0.0f) << pin;
  // a faulted display is not activated again without a configure
  rig.device.deactivate();
  EXPECT_THROW(rig.device.activate(), config::Error);
}

// a display that refuses module writes (an electrical fault) but still takes other requests
class RefusesWrites final : public usb::Emulator {
 public:
  explicit RefusesWrites(std::shared_ptr<MetecEmulator> inner) : inner_(std::move(inner)) {}
  usb::Outcome control(const usb::ControlSetup& s, std::uint8_t* data, std::uint16_t length) override {
    if (refuse && s.request >= kWriteModule && s.request < kWriteModule + kMaxModules) return {usb::Status::io, 0};
    return inner_->control(s, data, length);
  }
  usb::Outcome out(std::uint8_t e, const std::uint8_t* d, int n) override { return inner_->out(e, d, n); }
  usb::Outcome in(std::uint8_t e, std::uint8_t* d, int n) override { return inner_->in(e, d, n); }
  std::atomic<bool> refuse{false};

 private:
  std::shared_ptr<MetecEmulator> inner_;
};

TEST(MetecDevice, AFailedWriteSwitchesTheHighVoltageOff) {
  auto emulator = std::make_shared<MetecEmulator>();
  auto refusing = std::make_shared<RefusesWrites>(emulator);
  usb::FakeDevice d = usb::emulated_device("metec", refusing);
  auto bus = std::make_unique<usb::FakeBus>();
  bus->add(d);
  MetecTactileDevice device({}, std::move(bus));
  device.configure();
  device.activate();
  device.write(rt::now_ns(), 0x0001);
  ASSERT_TRUE(eventually([&] { return emulator->cell(0) == 0x80; }));
  ASSERT_TRUE(emulator->high_voltage());
  refusing->refuse = true;
  device.write(rt::now_ns(), 0x0003);
  ASSERT_TRUE(eventually([&] { return device.faulted(); }));
  EXPECT_FALSE(emulator->high_voltage()) << "a fault switches the high voltage off: every pin drops";
  EXPECT_EQ(emulator->dot_level(0, 1, rt::now_ns() + 30 * kMs), 0.0);
}

TEST(MetecDevice, UnplugIsAFaultAndNothingHangs) {
  auto rig = std::make_unique<Rig>();
  rig->device.configure();
  rig->device.activate();
  rig->on.cable->unplugged = true;
  ASSERT_TRUE(eventually([&] { return rig->device.faulted(); }));
  EXPECT_TRUE(rig->device.unplugged());
  rig->device.write(rt::now_ns(), 0xFFFF);
  rig->device.deactivate();
  rig.reset();
}

TEST(MetecDevice, TheEmergencyStopSwitchesTheHighVoltageOff) {
  Rig rig;
  rig.device.configure();
  rig.device.activate();
  usb::run_emergency_stops();
  const auto& c = *rig.on.cable;
  EXPECT_EQ(c.emergencies.load(), 1);
  EXPECT_EQ(c.emergency_request.load(), kSetHighVoltage);
  ASSERT_EQ(c.emergency_length.load(), 1);
  EXPECT_EQ(c.emergency_bytes[0], kHighVoltageOff);
}

TEST(MetecDevice, ConfigureErrorsSayTheFix) {
  MetecParams p;
  p.first_cell = 14;  // cells 14 and 15 fit the 16 cells; 15 and 16 do not
  Rig fits(p);
  fits.device.configure();
  p.first_cell = 15;
  Rig too_far(p);
  std::string error = configure_error(too_far.device);
  EXPECT_NE(error.find("need cells 15 .. 16, the display has 16"), std::string::npos) << error;
  EXPECT_NE(error.find("fix: set first_cell to 0 .. 14"), std::string::npos) << error;

  MetecParams wide;
  wide.cols = 9;
  Rig bad(wide);
  error = configure_error(bad.device);
  EXPECT_NE(error.find("cols is 9"), std::string::npos) << error;

  MetecTactileDevice absent({}, std::make_unique<usb::FakeBus>());
  error = configure_error(absent);
  EXPECT_NE(error.find("no Metec Braille cells (USB 0452:0100) found"), std::string::npos) << error;

  Rig denied({}, usb::Status::access);
  error = configure_error(denied.device);
  EXPECT_NE(error.find("permission denied"), std::string::npos) << error;
  EXPECT_NE(error.find("ATTRS{idVendor}==\"0452\", ATTRS{idProduct}==\"0100\""), std::string::npos) << error;

  Rig busy({}, usb::Status::busy);
  error = configure_error(busy.device);
  EXPECT_NE(error.find("systemctl stop brltty"), std::string::npos) << error;
}

TEST(MetecDevice, WriteAndShownAllocateNothing) {
  Rig rig;
  rig.device.configure();
  rig.device.activate();
  std::array<float, 32> levels{};
  test::AllocGuard guard;
  for (int i = 0; i < 1000; ++i) {
    rig.device.write(rt::now_ns(), static_cast<std::uint32_t>(i));
    rig.device.shown(rt::now_ns(), levels.data(), 32);
  }
  EXPECT_EQ(guard.allocations(), 0u);
}

}  // namespace
}  // namespace enact::devices::metec
