// The Falcon backend against its emulator, in real time (its I/O thread runs): firmware
// upload with retries, homing, lock-step position tracking, force direction and limits, the
// silent-loop timeout, deactivate, unplug mid-run, a device that stops answering, the
// emergency stop (also from a real crash), the errors of configure, no allocation on the
// real-time side, and the safety layer on top.
#include "core/devices/falcon/falcon_device.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/config/yaml.h"
#include "core/devices/falcon/emulator.h"
#include "core/devices/safety.h"
#include "core/rt/clock.h"
#include "tests/devices/usb_test_util.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/test_util.h"

namespace enact::devices::falcon {
namespace {

using test::eventually;

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kUs = 1'000;

struct Rig {
  test::OnBus<FalconEmulator> on;
  FalconForceDevice device;
  Rig(FalconEmulatorParams e = {}, FalconParams f = {}, usb::Status open_status = usb::Status::ok)
      : on("falcon", std::make_shared<FalconEmulator>(e), open_status), device(f, std::move(on.bus)) {}
};

// the message of configure()'s refusal
std::string configure_error(FalconForceDevice& d) { return test::error_of([&] { d.configure(); }); }

std::string firmware_file(const test::TempDir& dir, std::size_t n) {
  std::string bytes(n, '\0');
  for (std::size_t i = 0; i < n; ++i) bytes[i] = static_cast<char>((i * 53 + 7) & 0xFF);
  test::write_file(dir.file("falcon.bin"), bytes);
  return dir.file("falcon.bin");
}

ForceSample read_now(ForceDevice& d) {
  ForceSample s;
  d.read(rt::now_ns(), s);
  return s;
}

// keep writing a force (as the loop does) until the emulated motors push with `want`
bool pushes(ForceDevice& d, FalconEmulator& emu, const Vec3& force, const Vec3& want, double tolerance_n) {
  return eventually([&] {
    d.write(rt::now_ns(), force);
    return math::norm(emu.motor_force_n() - want) < tolerance_n;
  });
}

TEST(FalconDevice, UploadsTheFirmwareThroughFailedHandshakesWithRetries) {
  test::TempDir dir;
  FalconEmulatorParams e;
  e.firmware_running = false;
  e.handshake_failures = 25;  // the whole first load (20 tries) and 5 of the second fail
  FalconParams f;
  f.firmware = firmware_file(dir, 300);
  f.handshake_tries = 20;
  f.firmware_attempts = 3;
  Rig rig(e, f);
  rig.device.configure();
  EXPECT_TRUE(rig.device.uploaded_firmware());
  EXPECT_EQ(rig.on.emulator->check_messages(), 26);
  const std::string want = test::read_file(f.firmware);
  const auto got = rig.on.emulator->firmware();
  EXPECT_EQ(std::string(got.begin(), got.end()), want);
  EXPECT_TRUE(rig.on.emulator->running());
}

TEST(FalconDevice, GivesUpAfterItsAttemptsSayingWhy) {
  test::TempDir dir;
  FalconEmulatorParams e;
  e.firmware_running = false;
  e.handshake_failures = 1000;
  FalconParams f;
  f.firmware = firmware_file(dir, 100);
  f.handshake_tries = 4;
  f.firmware_attempts = 2;
  Rig rig(e, f);
  const std::string error = configure_error(rig.device);
  EXPECT_NE(error.find("failed 2 times"), std::string::npos) << error;
  EXPECT_NE(error.find("wrongly"), std::string::npos) << error;
  EXPECT_NE(error.find("fix:"), std::string::npos) << error;
  EXPECT_EQ(rig.on.emulator->check_messages(), 8);
}

TEST(FalconDevice, ARunningFirmwareIsNotUploadedAgainAndAMissingOneNeedsTheFile) {
  FalconParams f;
  f.firmware = "/nonexistent/falcon.bin";  // never read: the firmware runs already
  Rig running({}, f);
  running.device.configure();
  EXPECT_FALSE(running.device.uploaded_firmware());
  EXPECT_EQ(running.on.emulator->check_messages(), 0);

  FalconEmulatorParams e;
  e.firmware_running = false;
  Rig booting(e, {});
  const std::string error = configure_error(booting.device);
  EXPECT_NE(error.find("firmware is not running"), std::string::npos) << error;
  EXPECT_NE(error.find("fix: set firmware"), std::string::npos) << error;
}

TEST(FalconDevice, AbsentDeniedAndBusyDevicesAreClearErrors) {
  FalconForceDevice absent({}, std::make_unique<usb::FakeBus>());
  std::string error = configure_error(absent);
  EXPECT_NE(error.find("no Novint Falcon (USB 0403:cb48) found"), std::string::npos) << error;
  EXPECT_NE(error.find("fix: plug it in"), std::string::npos) << error;

  Rig denied({}, {}, usb::Status::access);
  error = configure_error(denied.device);
  EXPECT_NE(error.find("permission denied"), std::string::npos) << error;
  EXPECT_NE(error.find("99-enact.rules"), std::string::npos) << error;
  EXPECT_NE(error.find("ATTRS{idVendor}==\"0403\", ATTRS{idProduct}==\"cb48\""), std::string::npos) << error;

  Rig busy({}, {}, usb::Status::busy);
  error = configure_error(busy.device);
  EXPECT_NE(error.find("claimed by another program"), std::string::npos) << error;
}

TEST(FalconDevice, HomingWaitsUntilTheGripPassesTheIndex) {
  // un-homed; the emulated hand pushes the grip all the way in (enact +y: towards the base)
  // and back, after 0.2 s
  test::TempDir dir;
  test::write_file(dir.file("home.csv"), "t_s,x_m,y_m,z_m\n0,0,0,0\n0.2,0,0,0\n0.7,0,0.045,0\n1.2,0,0,0\n");
  FalconEmulatorParams e;
  e.homed = false;
  e.grip.hand_path = dir.file("home.csv");
  FalconParams f;
  f.homing_timeout_s = 20.0;
  Rig rig(e, f);
  rig.device.configure();
  EXPECT_EQ(rig.on.emulator->homed(), kAllHomed);
  // homed: the position is right (before, the encoders counted from the power-up position)
  rig.device.activate();
  ASSERT_TRUE(eventually([&] {
    const ForceSample s = read_now(rig.device);
    return s.faults == 0 && math::norm(s.position_m - rig.on.emulator->grip_position_m()) < 2e-4;
  }));
}

TEST(FalconDevice, HomingTimesOutWithTheGesture) {
  FalconEmulatorParams e;
  e.homed = false;
  FalconParams f;
  f.homing_timeout_s = 0.2;
  Rig rig(e, f);
  const std::string error = configure_error(rig.device);
  EXPECT_NE(error.find("did not home within 0.2 s"), std::string::npos) << error;
  EXPECT_NE(error.find("all the way out"), std::string::npos) << error;
}

TEST(FalconDevice, ReadsTrackTheMovingGrip) {
  // the hand drags the grip 20 mm along x and back in 1 s
  test::TempDir dir;
  test::write_file(dir.file("move.csv"), "t_s,x_m,y_m,z_m\n0,-0.01,0.005,0.01\n0.5,0.01,0.005,0.01\n1,-0.01,0.005,0.01\n");
  FalconEmulatorParams e;
  e.grip.hand_path = dir.file("move.csv");
  e.grip.start_m = {-0.01, 0.005, 0.01};
  Rig rig(e);
  rig.device.configure();
  rig.device.activate();
  // every read: between where the grip was just before and just after it (the read sample
  // lies in between, whatever the scheduling), give or take the encoders' resolution and the
  // travel over the sample's age (at most stale_s: 5 ms at 40 mm/s), plus the travel over the
  // longest a thread of this machine was held up in the same run (the I/O thread stamps a
  // sample when it runs, after the exchange: on a busy machine, that much later)
  constexpr double kTolerance_m = 3e-4, kSpeed_m_per_s = 0.04;
  std::int64_t held_up_ns = 0;
  double worst = 0.0, moved = 0.0;
  int reads = 0;
  Vec3 first;
  const std::uint64_t exchanges = rig.device.exchanges();
  const auto start = rt::now_ns();
  const auto end = start + 800 * kMs;
  while (rt::now_ns() < end) {
    rig.device.write(rt::now_ns(), {});
    ForceSample s;
    const Vec3 before = rig.on.emulator->grip_position_m();
    const bool ok = rig.device.read(rt::now_ns(), s);
    const Vec3 after = rig.on.emulator->grip_position_m();
    if (ok) {
      if (reads++ == 0) first = s.position_m;
      // the distance from the box spanned by before and after
      const Vec3 lo{std::min(before.x, after.x), std::min(before.y, after.y), std::min(before.z, after.z)};
      const Vec3 hi{std::max(before.x, after.x), std::max(before.y, after.y), std::max(before.z, after.z)};
      const Vec3 p = s.position_m;
      const Vec3 out{std::max({lo.x - p.x, p.x - hi.x, 0.0}), std::max({lo.y - p.y, p.y - hi.y, 0.0}), std::max({lo.z - p.z, p.z - hi.z, 0.0})};
      worst = std::max(worst, math::norm(out));
      moved = std::max(moved, math::norm(s.position_m - first));
    }
    const std::int64_t asleep_ns = rt::now_ns();
    std::this_thread::sleep_for(std::chrono::microseconds(500));
    held_up_ns = std::max(held_up_ns, rt::now_ns() - asleep_ns - 500 * kUs);
  }
  const double tolerance_m = kTolerance_m + kSpeed_m_per_s * static_cast<double>(held_up_ns) * 1e-9;
  std::printf("[ falcon ] %d reads, worst distance from the grip %.3g m (bound %.3g m: this thread held up %.3g ms at most) while moving %.3g m; %.0f lock-step exchanges per second, %llu missed\n", reads, worst,
              tolerance_m, static_cast<double>(held_up_ns) * 1e-6, moved, static_cast<double>(rig.device.exchanges() - exchanges) / (static_cast<double>(rt::now_ns() - start) * 1e-9),
              static_cast<unsigned long long>(rig.device.missed()));
  EXPECT_GT(reads, 100);
  EXPECT_GT(moved, 0.01) << "the grip did not move: the comparison above was vacuous";
  EXPECT_LT(worst, tolerance_m);
}

TEST(FalconDevice, ForcesKeepTheirDirectionAndAreClampedToMaxForce) {
  Rig rig;
  rig.device.configure();
  rig.device.activate();
  // the motors push along the command, in the enact frame (int16 commands: about 1 mN steps)
  EXPECT_TRUE(pushes(rig.device, *rig.on.emulator, {0, 0, 3}, {0, 0, 3}, 0.02));
  EXPECT_TRUE(pushes(rig.device, *rig.on.emulator, {-1.5, 2, 0.5}, {-1.5, 2, 0.5}, 0.02));
  // 12 N along y: 8 N along y
  EXPECT_TRUE(pushes(rig.device, *rig.on.emulator, {0, 12, 0}, {0, 8, 0}, 0.05));
  // NaN: nothing
  EXPECT_TRUE(pushes(rig.device, *rig.on.emulator, {NAN, 1, 0}, {0, 0, 0}, 1e-9));
}

TEST(FalconDevice, ALoopThatStopsWritingGetsZeroForce) {
  Rig rig;
  rig.device.configure();
  rig.device.activate();
  ASSERT_TRUE(pushes(rig.device, *rig.on.emulator, {2, 0, 0}, {2, 0, 0}, 0.02));
  // no more writes: the I/O thread zeroes the force on its own
  EXPECT_TRUE(eventually([&] { return math::norm(rig.on.emulator->motor_force_n()) < 1e-9; }));
}

TEST(FalconDevice, DeactivateReturnsAfterAZeroPacketWentOut) {
  Rig rig;
  rig.device.configure();
  rig.device.activate();
  ASSERT_TRUE(pushes(rig.device, *rig.on.emulator, {3, 0, 0}, {3, 0, 0}, 0.02));
  rig.device.write(rt::now_ns(), {3, 0, 0});
  rig.device.deactivate();
  EXPECT_EQ(rig.on.emulator->last_command().motor, (std::array<std::int16_t, 3>{}));
  // inactive: reads are device errors, writes do nothing
  EXPECT_EQ(read_now(rig.device).faults, bit(DeviceFault::device_error));
  rig.device.write(rt::now_ns(), {3, 0, 0});
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(rig.on.emulator->last_command().motor, (std::array<std::int16_t, 3>{}));
}

TEST(FalconDevice, UnplugMidRunIsAFaultAndNothingHangs) {
  auto rig = std::make_unique<Rig>();
  rig->device.configure();
  rig->device.activate();
  ASSERT_TRUE(eventually([&] { return read_now(rig->device).faults == 0; }));
  rig->on.cable->unplugged = true;
  EXPECT_TRUE(eventually([&] { return rig->device.unplugged(); }));
  const ForceSample s = read_now(rig->device);
  EXPECT_TRUE(has(s.faults, DeviceFault::device_error));
  rig->device.write(rt::now_ns(), {1, 0, 0});
  rig->device.deactivate();
  rig.reset();  // the destructor returns
}

TEST(FalconDevice, ADeviceThatStopsAnsweringIsAnErrorOnceItsSampleIsOlderThanStaleS) {
  FalconParams f;
  f.stale_s = 0.005;
  Rig rig({}, f);
  rig.device.configure();
  rig.device.activate();
  ASSERT_TRUE(eventually([&] { return read_now(rig.device).faults == 0; }));
  const std::int64_t stalled_at = rt::now_ns();
  rig.on.cable->stalled = true;
  // in real time: reported, once the newest sample is older than stale_s
  ASSERT_TRUE(eventually([&] { return has(read_now(rig.device).faults, DeviceFault::device_error); }));
  std::printf("[ falcon ] a stalled device was reported %.2f ms after it stopped answering\n", static_cast<double>(rt::now_ns() - stalled_at) / 1e6);
  // the rule itself, at chosen times: the newest sample ...
  ForceSample s;
  rig.device.read(rt::now_ns(), s);
  const std::int64_t t = s.time_ns;
  // ... is good up to stale_s after it was taken, an error after
  EXPECT_TRUE(rig.device.read(t + 4 * kMs, s));
  EXPECT_EQ(s.faults, 0u);
  EXPECT_FALSE(rig.device.read(t + 6 * kMs, s));
  EXPECT_EQ(s.faults, bit(DeviceFault::device_error));
  // answering again: good again
  rig.on.cable->stalled = false;
  EXPECT_TRUE(eventually([&] { return read_now(rig.device).faults == 0; }));
}

TEST(FalconDevice, TheEmergencyStopSendsOneZeroPacketAndHaltsTheThread) {
  Rig rig;
  rig.device.configure();
  rig.device.activate();
  ASSERT_TRUE(pushes(rig.device, *rig.on.emulator, {3, 0, 0}, {3, 0, 0}, 0.02));
  usb::run_emergency_stops();
  const auto& c = *rig.on.cable;
  EXPECT_EQ(c.emergencies.load(), 1);
  EXPECT_EQ(c.emergency_request.load(), -1) << "a bulk transfer";
  ASSERT_EQ(c.emergency_length.load(), 16);
  EXPECT_EQ(std::string(c.emergency_bytes.begin(), c.emergency_bytes.begin() + 16), "<AAAAAAAAAAAAAA>");
  // no packet after it
  const std::uint64_t packets = rig.on.emulator->packets();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_LE(rig.on.emulator->packets(), packets + 1);
}

TEST(FalconDevice, ACrashingDriverSendsTheZeroPacketFromItsSignalHandler) {
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // the driver: running, pushing 3 N, then it crashes
    close(fds[0]);
    try {
      Rig rig;
      rig.on.cable->emergency_fd = fds[1];
      rig.device.configure();
      rig.device.activate();
      for (int i = 0; i < 50; ++i) {
        rig.device.write(rt::now_ns(), {3, 0, 0});
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      raise(SIGSEGV);
    } catch (...) {
    }
    _exit(3);
  }
  close(fds[1]);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGSEGV) << "the driver still dies of its signal; status " << status;
  std::string got;
  char buf[64];
  for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) > 0;) got.append(buf, static_cast<std::size_t>(n));
  close(fds[0]);
  // [0xFF: a bulk transfer, 16 bytes] then the zero packet
  EXPECT_EQ(got, std::string("\xFF\x10") + "<AAAAAAAAAAAAAA>");
}

TEST(FalconDevice, ReadAndWriteAllocateNothing) {
  Rig rig;
  rig.device.configure();
  rig.device.activate();
  ForceSample s;
  test::AllocGuard guard;
  for (int i = 0; i < 1000; ++i) {
    rig.device.read(rt::now_ns(), s);
    rig.device.write(rt::now_ns(), {0.1 * i, 0, 0});
  }
  EXPECT_EQ(guard.allocations(), 0u);
}

TEST(FalconDevice, TheSafetyLayerClampsToMaxForceAndSaysSo) {
  FalconParams f;
  f.max_force_n = 6.0;
  test::OnBus<FalconEmulator> on("falcon", std::make_shared<FalconEmulator>());
  auto emulator = on.emulator;
  SafeForceDevice safe(std::make_unique<FalconForceDevice>(f, std::move(on.bus)));
  safe.configure();
  EXPECT_EQ(safe.profile().name, "falcon");
  EXPECT_EQ(safe.profile().peak_force_n, 6.0);
  safe.activate();
  EXPECT_TRUE(pushes(safe, *emulator, {0, 0, -10}, {0, 0, -6}, 0.05));
  ForceSample s;
  safe.read(rt::now_ns(), s);
  EXPECT_TRUE(has(s.faults, DeviceFault::clamped));
  EXPECT_GT(safe.clamps(), 0u);
  safe.deactivate();
  EXPECT_EQ(emulator->last_command().motor, (std::array<std::int16_t, 3>{}));
}

TEST(FalconDevice, BadParamsAreRefusedWithTheRange) {
  FalconParams f;
  f.stale_s = 0.02;
  Rig rig({}, f);
  const std::string error = configure_error(rig.device);
  EXPECT_NE(error.find("stale_s is 0.02"), std::string::npos) << error;
  EXPECT_NE(error.find("within 10 ms"), std::string::npos) << error;
}

}  // namespace
}  // namespace enact::devices::falcon
