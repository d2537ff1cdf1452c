// The safety layer: clamping to the peak force, NaN/Inf to zero, the watchdog ramp, zero
// force before disabling; observed through a recording fake device under it.
#include "core/devices/safety.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/config/yaml.h"
#include "core/devices/simulated_force.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/test_util.h"

namespace enact::devices {
namespace {

using math::Vec3;

using test::kMs;
constexpr std::int64_t kT0 = 2'000 * kMs;  // an arbitrary time of the last write

// what the wrapper did to the device under it, in order
struct Call {
  enum Kind { configure, activate, read, write, deactivate } kind;
  std::int64_t time_ns = 0;
  Vec3 force_n;
};

class RecordingDevice final : public ForceDevice {
 public:
  // the ERGOS profile; `step_limit_n_per_ms` 0 keeps its force step limit, else replaces it
  explicit RecordingDevice(std::vector<Call>& log, double step_limit_n_per_ms = 0.0)
      : log_(log), profile_(*devices::find_device_profile("ergos")) {
    if (step_limit_n_per_ms > 0.0) profile_.max_force_step_n_per_ms = step_limit_n_per_ms;
  }
  void configure() override { log_.push_back({Call::configure, 0, {}}); }
  void activate() override { log_.push_back({Call::activate, 0, {}}); }
  bool read(std::int64_t now_ns, ForceSample& out) noexcept override {
    log_.push_back({Call::read, now_ns, {}});
    out = {};
    out.time_ns = now_ns;
    out.faults = fail ? bit(DeviceFault::device_error) : 0u;
    return !fail;
  }
  void write(std::int64_t now_ns, const Vec3& force_n) noexcept override { log_.push_back({Call::write, now_ns, force_n}); }
  void deactivate() noexcept override { log_.push_back({Call::deactivate, 0, {}}); }
  const devices::DeviceProfile& profile() const override { return profile_; }
  bool fail = false;

 private:
  std::vector<Call>& log_;
  devices::DeviceProfile profile_;
};

struct Fixture {
  std::vector<Call> log;
  RecordingDevice* inner = nullptr;
  std::unique_ptr<SafeForceDevice> safe;

  // by default neither the re-engagement ramp nor the slew limit act (the tests of the
  // clamp, NaN and watchdog see the commands unshaped); the profile's limit with `real_limit`
  explicit Fixture(SafetyParams params = {.reengage_s = 0.0}, bool real_limit = false) {
    auto device = std::make_unique<RecordingDevice>(log, real_limit ? 0.0 : 1e12);
    inner = device.get();
    safe = std::make_unique<SafeForceDevice>(std::move(device), params);
    safe->configure();
    safe->activate();
    log.clear();
  }
  // the last force the inner device was sent
  Vec3 last_write() const {
    for (auto it = log.rbegin(); it != log.rend(); ++it) {
      if (it->kind == Call::write) return it->force_n;
    }
    return {std::nan(""), 0.0, 0.0};
  }
  ForceSample read(std::int64_t now_ns) {
    ForceSample s;
    safe->read(now_ns, s);
    return s;
  }
};

TEST(Safety, ClampToThePeakKeepsDirectionAndCounts) {
  Fixture f;
  f.safe->write(kT0, {300.0, 0.0, -400.0});  // 500 N, ERGOS peak 200 N
  EXPECT_LT(norm(f.last_write() - Vec3{120.0, 0.0, -160.0}), 1e-12);
  EXPECT_EQ(f.safe->clamps(), 1u);
  EXPECT_TRUE(has(f.read(kT0).faults, DeviceFault::clamped));
  EXPECT_TRUE(f.safe->faulted());
  // under the peak: passed through, the bit clears
  f.safe->write(kT0 + kMs, {3.0, 0.0, -4.0});
  EXPECT_EQ(f.last_write(), (Vec3{3.0, 0.0, -4.0}));
  EXPECT_EQ(f.safe->clamps(), 1u);
  EXPECT_EQ(f.read(kT0 + kMs).faults, 0u);
  EXPECT_FALSE(f.safe->faulted());
}

TEST(Safety, NonfiniteCommandsBecomeZeroAndCount) {
  Fixture f;
  const double inf = std::numeric_limits<double>::infinity();
  const Vec3 bad[] = {{std::nan(""), 1.0, 1.0}, {1.0, inf, 1.0}, {1.0, 1.0, -inf}};
  std::int64_t t = kT0;
  for (const Vec3& command : bad) {
    f.safe->write(t, command);
    EXPECT_EQ(f.last_write(), Vec3{});
    EXPECT_TRUE(has(f.read(t).faults, DeviceFault::nonfinite_command));
    t += kMs;
  }
  EXPECT_EQ(f.safe->nonfinite(), 3u);
  EXPECT_EQ(f.safe->clamps(), 0u);
}

TEST(Safety, WatchdogRampsTheLastCommandToZero) {
  Fixture f;  // watchdog 10 ms, ramp 5 ms
  const Vec3 command{0.0, 20.0, -40.0};
  f.safe->write(kT0, command);
  // within the watchdog time: the full command, nothing more sent
  for (const std::int64_t dt : {kMs, 9 * kMs, 10 * kMs}) {
    const std::size_t calls = f.log.size();
    const ForceSample s = f.read(kT0 + dt);
    EXPECT_FALSE(has(s.faults, DeviceFault::watchdog)) << dt;
    EXPECT_EQ(f.log.size(), calls + 1) << dt;  // the read only
    EXPECT_EQ(f.safe->sent_force_n(), command);
  }
  // half way down the ramp: half the command
  ForceSample s = f.read(kT0 + 12 * kMs + kMs / 2);
  EXPECT_EQ(f.log.back().kind, Call::write);
  EXPECT_EQ(f.log.back().time_ns, kT0 + 12 * kMs + kMs / 2);
  EXPECT_LT(norm(f.last_write() - command * 0.5), 1e-12);
  EXPECT_TRUE(has(s.faults, DeviceFault::watchdog));
  EXPECT_TRUE(f.safe->faulted());
  EXPECT_EQ(f.safe->watchdog_trips(), 1u);
  // at the end of the ramp and after: zero, one episode
  for (const std::int64_t dt : {15 * kMs, 16 * kMs, 500 * kMs}) {
    s = f.read(kT0 + dt);
    EXPECT_EQ(f.last_write(), Vec3{}) << dt;
    EXPECT_TRUE(has(s.faults, DeviceFault::watchdog)) << dt;
  }
  EXPECT_EQ(f.safe->watchdog_trips(), 1u);
  // a fresh write restores the command and ends the episode
  const std::int64_t t1 = kT0 + 600 * kMs;
  f.safe->write(t1, command);
  EXPECT_EQ(f.last_write(), command);
  s = f.read(t1 + kMs);
  EXPECT_FALSE(has(s.faults, DeviceFault::watchdog));
  EXPECT_FALSE(f.safe->faulted());
  // a second silence is a second episode
  f.read(t1 + 11 * kMs);
  EXPECT_EQ(f.safe->watchdog_trips(), 2u);
}

TEST(Safety, WatchdogWaitsForTheFirstCommand) {
  Fixture f;
  EXPECT_FALSE(has(f.read(kT0).faults, DeviceFault::watchdog));
  EXPECT_FALSE(has(f.read(kT0 + 1'000 * kMs).faults, DeviceFault::watchdog));
  EXPECT_EQ(f.safe->watchdog_trips(), 0u);
}

TEST(Safety, ZeroRampCutsAtOnce) {
  Fixture f({.watchdog_s = 0.002, .ramp_s = 0.0, .reengage_s = 0.0});
  f.safe->write(kT0, {10.0, 0.0, 0.0});
  f.read(kT0 + 2 * kMs);
  EXPECT_EQ(f.last_write(), (Vec3{10.0, 0.0, 0.0}));
  f.read(kT0 + 2 * kMs + 1);
  EXPECT_EQ(f.last_write(), Vec3{});
  EXPECT_EQ(f.safe->watchdog_trips(), 1u);
}

TEST(Safety, DeactivateZerosTheForceBeforeDisabling) {
  Fixture f;
  f.safe->write(kT0, {5.0, 5.0, 5.0});
  f.read(kT0 + kMs);
  f.safe->deactivate();
  ASSERT_GE(f.log.size(), 2u);
  const Call& zero = f.log[f.log.size() - 2];
  EXPECT_EQ(zero.kind, Call::write);
  EXPECT_EQ(zero.force_n, Vec3{});
  EXPECT_EQ(zero.time_ns, kT0 + kMs);  // the latest time seen
  EXPECT_EQ(f.log.back().kind, Call::deactivate);
}

TEST(Safety, DeviceErrorIsPassedOn) {
  Fixture f;
  f.inner->fail = true;
  ForceSample s;
  EXPECT_FALSE(f.safe->read(kT0, s));
  EXPECT_TRUE(has(s.faults, DeviceFault::device_error));
  EXPECT_TRUE(f.safe->faulted());
}

TEST(Safety, BadParamsAreRefusedWithAFix) {
  const SafetyParams bad[] = {{.watchdog_s = 0.0}, {.watchdog_s = std::nan("")}, {.ramp_s = -0.001}, {.reengage_s = -0.1}};
  for (const auto& p : bad) {
    std::vector<Call> log;
    SafeForceDevice safe(std::make_unique<RecordingDevice>(log), p);
    try {
      safe.configure();
      ADD_FAILURE() << "accepted";
    } catch (const config::Error& e) {
      EXPECT_NE(std::string(e.what()).find("fix:"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(log.empty());  // refused before the device is opened
  }
}

// the largest force step sent to the inner device, as a fraction of what the limit allows
// over the time since the previous write (at most 1 ms; the first: 1 ms)
double largest_step_fraction(const std::vector<Call>& log, double limit_n_per_ms) {
  double largest = 0.0;
  const Call* previous = nullptr;
  for (const Call& c : log) {
    if (c.kind != Call::write) continue;
    const std::int64_t dt_ns = previous ? std::min(c.time_ns - previous->time_ns, kMs) : kMs;
    const Vec3 before = previous ? previous->force_n : Vec3{};
    const double allowed_n = limit_n_per_ms * static_cast<double>(dt_ns) / static_cast<double>(kMs);
    largest = std::max(largest, norm(c.force_n - before) / allowed_n);
    previous = &c;
  }
  return largest;
}

TEST(Safety, SlewLimitBoundsEveryStepOfTheForce) {
  Fixture f({.reengage_s = 0.0}, true);
  const double limit = f.inner->profile().max_force_step_n_per_ms;
  ASSERT_EQ(limit, 10.0);
  // 0 to the 200 N peak at once, commanded at 5 kHz: a millisecond's 10 N at the first write
  // (nothing was sent before), then 2 N per 0.2 ms, the peak after 19 ms
  std::int64_t t = kT0;
  for (int i = 0; i < 250; ++i, t += kMs / 5) f.safe->write(t, {0.0, 0.0, -200.0});
  EXPECT_LE(largest_step_fraction(f.log, limit), 1.0 + 1e-9);
  EXPECT_NEAR(f.log[0].force_n.z, -10.0, 1e-9);
  EXPECT_NEAR(f.log[5].force_n.z, -20.0, 1e-9);  // 1 ms later
  EXPECT_EQ(f.last_write(), (Vec3{0.0, 0.0, -200.0}));
  EXPECT_GT(f.safe->slew_limited(), 0u);
  // the reverse after a silence of 8 ms (no watchdog yet): one millisecond's step, no more
  t += 8 * kMs;
  f.safe->write(t, {0.0, 0.0, 200.0});
  EXPECT_NEAR(f.last_write().z, -190.0, 1e-9);
  // switching off zeroes at once
  f.safe->deactivate();
  EXPECT_EQ(f.safe->sent_force_n(), Vec3{});
}

// the re-engagement after one kind of interruption: a constant command every 0.2 ms from t,
// which the force approaches from zero over reengage_s (100 ms); returns the time after t
// at which the force is at half the command
void expect_gentle_return(Fixture& f, std::int64_t t, const Vec3& command, const char* kind) {
  const std::size_t from = f.log.size();
  for (int i = 0; i <= 600; ++i) {
    f.safe->write(t + i * (kMs / 5), command);
    f.read(t + i * (kMs / 5) + 1);
  }
  std::vector<Call> writes;
  for (std::size_t i = from; i < f.log.size(); ++i) {
    if (f.log[i].kind == Call::write) writes.push_back(f.log[i]);
  }
  ASSERT_EQ(writes.size(), 601u) << kind;
  EXPECT_EQ(writes[0].force_n, Vec3{}) << kind << ": the first force after the interruption";
  EXPECT_LT(norm(writes[250].force_n - command * 0.5), 1e-9) << kind << ": half way (50 ms)";
  EXPECT_EQ(writes[500].force_n, command) << kind << ": all of it after 100 ms";
}

TEST(Safety, ForceReturnsGentlyAfterEveryInterruption) {
  Fixture f(SafetyParams{}, true);  // watchdog 10 ms, ramp 5 ms, re-engagement 100 ms
  const Vec3 command{0.0, 12.0, -24.0};
  // activation
  expect_gentle_return(f, kT0, command, "activation");
  EXPECT_EQ(f.safe->reengagements(), 1u);
  // a watchdog episode: 50 ms without a command (the force ramps down, at the profile's
  // limit at most), then commands again
  std::int64_t t = f.log.back().time_ns;
  for (int i = 0; i < 250; ++i) f.read(t += kMs / 5);
  ASSERT_EQ(f.safe->watchdog_trips(), 1u);
  ASSERT_EQ(f.safe->sent_force_n(), Vec3{});
  expect_gentle_return(f, t + kMs, command, "watchdog episode");
  // failed reads of the device for 10 ms (a USB error: the force goes to zero at the
  // profile's limit), then it reads well again
  t = f.log.back().time_ns;
  f.inner->fail = true;
  for (int i = 0; i < 50; ++i) f.read(t += kMs / 5);
  ASSERT_EQ(f.safe->sent_force_n(), Vec3{});
  f.inner->fail = false;
  expect_gentle_return(f, t + kMs, command, "device error");
  EXPECT_EQ(f.safe->reengagements(), 3u);
  // and nowhere a step beyond the profile's limit
  EXPECT_LE(largest_step_fraction(f.log, f.inner->profile().max_force_step_n_per_ms), 1.0 + 1e-9);
}

TEST(Safety, NoFaultSequenceStepsTheForceBeyondTheLimit) {
  // random commands (up to 10 times the peak, NaN now and then), silences that trip the
  // watchdog, device errors, at random intervals from 10 us to 30 ms
  Fixture f(SafetyParams{}, true);
  std::mt19937 rng(18);
  std::uniform_real_distribution<double> force(-2000.0, 2000.0), u(0.0, 1.0);
  std::int64_t t = kT0;
  for (int i = 0; i < 20'000; ++i) {
    t += static_cast<std::int64_t>(10'000 + u(rng) * (u(rng) < 0.02 ? 30 * kMs : kMs));
    f.inner->fail = u(rng) < 0.01;
    f.read(t);
    if (u(rng) < 0.9) f.safe->write(t, u(rng) < 0.01 ? Vec3{std::nan(""), 0.0, 0.0} : Vec3{force(rng), force(rng), force(rng)});
  }
  EXPECT_GT(f.safe->watchdog_trips(), 0u);
  EXPECT_GT(f.safe->slew_limited(), 0u);
  EXPECT_LE(largest_step_fraction(f.log, f.inner->profile().max_force_step_n_per_ms), 1.0 + 1e-9);
}

// each sample says the force acting on the hand as it was read: the last force the inner
// device was sent (by the watchdog's ramp in this read, or by the last write), not the
// command, through clamps, ramps back, the slew limit, watchdog episodes and device errors
TEST(Safety, EachSampleCarriesTheForceActingOnTheHand) {
  Fixture f(SafetyParams{}, true);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> force(-60.0, 60.0), u(0.0, 1.0);
  std::int64_t t = kT0;
  std::size_t differ = 0;
  for (int i = 0; i < 20'000; ++i) {
    t += static_cast<std::int64_t>(10'000 + u(rng) * (u(rng) < 0.02 ? 30 * kMs : kMs));
    f.inner->fail = u(rng) < 0.01;
    const ForceSample s = f.read(t);
    const Vec3 written = f.last_write();  // (NaN: nothing written yet, the force is zero)
    ASSERT_EQ(s.force_n, std::isnan(written.x) ? Vec3{} : written) << "read " << i;
    if (u(rng) < 0.9) {
      const Vec3 command{force(rng), force(rng), force(rng)};
      f.safe->write(t, command);
      differ += !(f.last_write() == command);
    }
  }
  EXPECT_GT(f.safe->watchdog_trips(), 0u);
  EXPECT_GT(differ, 1000u) << "the sequence hardly shaped the commands: nothing to tell apart";
}

// over the simulated device: a loop with clamps, NaN and a watchdog episode allocates nothing
TEST(Safety, ReadAndWriteOverTheSimulatedDeviceAllocateNothing) {
  SimulatedForceParams p;
  SafeForceDevice safe(std::make_unique<SimulatedForceDevice>(p));
  safe.configure();
  safe.activate();
  ForceSample s;
  std::size_t allocations = 0;
  {
    test::AllocGuard guard;
    for (std::int64_t t = 0; t <= 400 * kMs; t += kMs / 5) {
      safe.read(t, s);
      if (t < 200 * kMs) safe.write(t, t % (3 * kMs) == 0 ? Vec3{std::nan(""), 0.0, 0.0} : Vec3{0.0, 0.0, -500.0});
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(safe.clamps(), 0u);
  EXPECT_GT(safe.nonfinite(), 0u);
  EXPECT_EQ(safe.watchdog_trips(), 1u);
  EXPECT_EQ(safe.sent_force_n(), Vec3{});
}

}  // namespace
}  // namespace enact::devices
