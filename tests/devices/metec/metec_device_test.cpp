// The Metec backend against its emulator, in real time (its I/O thread runs): the pins reach
// the cells through the mapping, only changed modules are rewritten, shown() is what the
// cells physically show (the emulator's dots, rate limited), high voltage off with the pins
// lowered on deactivate, on a fault and on unplug, the emergency stop, configure's errors,
// and no allocation on the real-time side.
#include "core/devices/metec/metec_device.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
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

// one clock for the backend's model of the cells and the emulated cells, held still: the
// motion of both is compared at chosen times, whatever the threads' scheduling
std::atomic<std::int64_t> g_now{5'000'000'000};
std::int64_t manual_clock() { return g_now.load(); }

// the backend and the emulated display on the manual clock
MetecEmulatorParams clocked_display() {
  MetecEmulatorParams e;
  e.clock = manual_clock;
  return e;
}
MetecParams clocked_backend() {
  MetecParams p;
  p.clock = manual_clock;
  return p;
}
struct ClockedRig {
  test::OnBus<MetecEmulator> on{"metec", std::make_shared<MetecEmulator>(clocked_display())};
  MetecTactileDevice device{clocked_backend(), std::move(on.bus)};
};

TEST(MetecDevice, PinsReachTheCellsAndShownIsWhatTheCellsPhysicallyShow) {
  ClockedRig rig;
  auto& on = rig.on;
  auto& device = rig.device;
  const Layout l{4, 4, 0};
  device.configure();
  device.activate();
  // the left pin column and pin 15, written at T
  const std::int64_t t0 = g_now.load();
  const std::uint32_t pins = 0x1111 | (1u << 15);
  device.write(t0, pins);
  ASSERT_TRUE(eventually([&] { return shown(device, t0 + 100 * kMs)[15] == 1.0f; })) << "the backend took the write";
  EXPECT_EQ(on.emulator->cell(0), 0xE2);
  EXPECT_EQ(on.emulator->cell(1), 0x01);
  // the cells rise over 24 ms from T; shown() says the same at every time
  for (std::int64_t later : {0 * kMs, 6 * kMs, 12 * kMs, 24 * kMs, 30 * kMs}) {
    const auto model = shown(device, t0 + later);
    const auto physical = dots(*on.emulator, l, t0 + later);
    for (int pin = 0; pin < 16; ++pin) {
      const auto i = static_cast<std::size_t>(pin);
      EXPECT_NEAR(model[i], physical[i], 1e-6) << "pin " << pin << " at +" << later / kMs << " ms";
      const double want = ((pins >> pin) & 1u) ? std::min(1.0, static_cast<double>(later) / 24e6) : 0.0;
      EXPECT_NEAR(physical[i], want, 1e-9) << "pin " << pin << " at +" << later / kMs << " ms";
    }
  }
  // a pin lowered mid-stroke reverses from where it was (12 ms up: half way)
  g_now += 12 * kMs;
  device.write(g_now.load(), pins & ~1u);
  ASSERT_TRUE(eventually([&] { return on.emulator->cell(0) == 0x62; }));
  ASSERT_TRUE(eventually([&] { return shown(device, g_now.load() + 100 * kMs)[0] == 0.0f; }));
  EXPECT_NEAR(shown(device, g_now.load() + 6 * kMs)[0], 0.25, 1e-6);
  EXPECT_NEAR(on.emulator->dot_level(0, 1, g_now.load() + 6 * kMs), 0.25, 1e-9);
  device.deactivate();
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
  ClockedRig rig;
  auto& on = rig.on;
  auto& device = rig.device;
  device.configure();
  device.activate();
  device.write(g_now.load(), 0xFFFF);
  ASSERT_TRUE(eventually([&] { return on.emulator->cell(0) == 0xFF; }));
  g_now += 100 * kMs;  // all up
  device.deactivate();
  EXPECT_FALSE(on.emulator->high_voltage());
  EXPECT_EQ(on.emulator->cell(0), 0);
  EXPECT_EQ(on.emulator->cell(1), 0);
  // falling from now, in the cells and in shown(): half way at 12 ms, down at 24 ms
  const std::int64_t t = g_now.load();
  for (std::int64_t later : {12 * kMs, 24 * kMs}) {
    const auto levels = shown(device, t + later);
    const auto physical = dots(*on.emulator, {4, 4, 0}, t + later);
    for (int pin = 0; pin < 16; ++pin) {
      EXPECT_NEAR(levels[static_cast<std::size_t>(pin)], later == 12 * kMs ? 0.5 : 0.0, 1e-6) << pin;
      EXPECT_NEAR(physical[static_cast<std::size_t>(pin)], later == 12 * kMs ? 0.5 : 0.0, 1e-9) << pin;
    }
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
