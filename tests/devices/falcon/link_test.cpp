// The Falcon's start-up and lock-step steps over a fake transport and the emulator: the FT232
// requests against the sequences libnifalcon documents (written out by hand), the handshake
// with a boot loader that fails the first check messages, the firmware upload echoed chunk by
// chunk, and exchanges whose encoder counts give back the emulated grip's position.
#include "core/devices/falcon/link.h"

#include <gtest/gtest.h>

#include <atomic>

#include "core/devices/falcon/emulator.h"
#include "core/devices/falcon/kinematics.h"
#include "tests/devices/usb_test_util.h"

namespace enact::devices::falcon {
namespace {

using test::Recording;

std::atomic<std::int64_t> g_now{1'000'000'000};
std::int64_t manual_clock() { return g_now.load(); }

FalconEmulatorParams booting(int handshake_failures) {
  FalconEmulatorParams e;
  e.firmware_running = false;
  e.handshake_failures = handshake_failures;
  e.clock = manual_clock;
  return e;
}

std::vector<std::uint8_t> some_firmware(std::size_t n) {
  std::vector<std::uint8_t> f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = static_cast<std::uint8_t>((i * 37 + 11) & 0xFF);
  return f;
}

struct Wired {
  std::shared_ptr<FalconEmulator> emulator;
  std::shared_ptr<Recording> recording;
  std::shared_ptr<usb::FakeCable> cable = std::make_shared<usb::FakeCable>();
  usb::FakeTransport transport;
  Link link;
  explicit Wired(FalconEmulatorParams e)
      : emulator(std::make_shared<FalconEmulator>(e)), recording(std::make_shared<Recording>(emulator)), transport(recording, cable), link(transport) {}
};

// (bRequest, wValue) of every control request, all vendor host-to-device with index 0
std::vector<std::pair<int, int>> requests(const Recording& r) {
  std::vector<std::pair<int, int>> out;
  for (const auto& s : r.controls) {
    EXPECT_EQ(s.request_type, 0x40);
    EXPECT_EQ(s.index, 0);
    out.emplace_back(s.request, s.value);
  }
  return out;
}

TEST(FalconLink, NormalModeIsLatencyOneBaudTwoAndBothPurges) {
  Wired w(booting(0));
  std::string why;
  ASSERT_TRUE(w.link.enter_normal_mode(why)) << why;
  // libnifalcon's setNormalMode: latency timer 1, baud divisor 2, purge RX (1), purge TX (2)
  const std::vector<std::pair<int, int>> want = {{0x09, 1}, {0x03, 0x0002}, {0x00, 1}, {0x00, 2}};
  EXPECT_EQ(requests(*w.recording), want);
}

TEST(FalconLink, TheBootLoaderSequenceIsLibnifalconsAndSurvivesFailedChecks) {
  Wired w(booting(3));
  std::string why;
  ASSERT_TRUE(w.link.enter_boot_loader(5, why)) << why;
  // purge RX, purge TX, latency 16, 9600 baud (0x4138), 8N1 (8), no flow control, RTS low
  // (0x0200), DTR low (0x0100), DTR high (0x0101); after the check: DTR low, baud divisor 0x15
  const std::vector<std::pair<int, int>> want = {{0, 1},      {0, 2},      {9, 16},     {3, 0x4138}, {4, 8},   {2, 0},
                                                 {1, 0x0200}, {1, 0x0100}, {1, 0x0101}, {1, 0x0100}, {3, 0x15}};
  EXPECT_EQ(requests(*w.recording), want);
  // four check messages (three answered wrongly), then the boot byte 'A'
  const std::vector<std::uint8_t> check = {0x0A, 0x43, 0x0D};
  ASSERT_EQ(w.recording->sent.size(), 5u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(w.recording->sent[static_cast<std::size_t>(i)], check) << i;
  EXPECT_EQ(w.recording->sent[4], std::vector<std::uint8_t>{0x41});
  EXPECT_EQ(w.emulator->check_messages(), 4);
}

TEST(FalconLink, TooManyFailedChecksGiveUpWithTheReason) {
  Wired w(booting(10));
  std::string why;
  EXPECT_FALSE(w.link.enter_boot_loader(3, why));
  EXPECT_NE(why.find("3 times wrongly"), std::string::npos) << why;
  EXPECT_EQ(w.emulator->check_messages(), 3);
}

TEST(FalconLink, TheFirmwareGoesIn62ByteChunksEachEchoedAndThenRuns) {
  Wired w(booting(1));
  std::string why;
  ASSERT_TRUE(w.link.enter_boot_loader(5, why)) << why;
  const auto firmware = some_firmware(200);
  w.recording->sent.clear();
  ASSERT_TRUE(w.link.upload(firmware, why)) << why;
  // 62 + 62 + 62 + 14
  ASSERT_EQ(w.recording->sent.size(), 4u);
  EXPECT_EQ(w.recording->sent[0].size(), 62u);
  EXPECT_EQ(w.recording->sent[3].size(), 14u);
  EXPECT_EQ(w.emulator->firmware(), firmware);
  EXPECT_FALSE(w.emulator->running());
  ASSERT_TRUE(w.link.enter_normal_mode(why)) << why;
  EXPECT_TRUE(w.emulator->running());
  Reading r;
  EXPECT_EQ(w.link.exchange(Command{}, r, 20'000'000), usb::Status::ok);
}

TEST(FalconLink, ABadEchoFailsTheUpload) {
  Wired w(booting(0));
  std::string why;
  ASSERT_TRUE(w.link.enter_boot_loader(5, why)) << why;
  w.recording->corrupt_in = true;
  EXPECT_FALSE(w.link.upload(some_firmware(100), why));
  EXPECT_NE(why.find("not echoed"), std::string::npos) << why;
}

TEST(FalconLink, ExchangesCarryTheCommandAndTheGripsPosition) {
  FalconEmulatorParams e;
  e.clock = manual_clock;
  e.grip.start_m = {0.012, -0.008, 0.006};
  Wired w(e);
  std::string why;
  ASSERT_TRUE(w.link.enter_normal_mode(why));
  Command c;
  c.motor = {120, -340, 560};
  c.leds = kLedGreen;
  c.homing = true;
  Reading r;
  ASSERT_EQ(w.link.exchange(c, r, 20'000'000), usb::Status::ok);
  EXPECT_EQ(w.emulator->last_command(), c);
  EXPECT_EQ(r.homed, kAllHomed);
  // the encoder counts through the forward kinematics: the grip, within the encoders' resolution
  Vec3 p;
  ASSERT_TRUE(forward({angle_of(r.encoder[0]), angle_of(r.encoder[1]), angle_of(r.encoder[2])}, {0, 0, kCentreZ_m}, p));
  EXPECT_LT(math::norm(to_enact(p) - w.emulator->grip_position_m()), 1e-4);
  EXPECT_LT(math::norm(to_enact(p) - e.grip.start_m), 1e-4);
}

TEST(FalconLink, AnUnpluggedDeviceAnswersNoDevice) {
  FalconEmulatorParams e;
  e.clock = manual_clock;
  Wired w(e);
  w.cable->unplugged = true;
  Reading r;
  EXPECT_EQ(w.link.exchange(Command{}, r, 20'000'000), usb::Status::no_device);
}

}  // namespace
}  // namespace enact::devices::falcon
