// The machine probe: its figures, its cache per boot, and the wait a loop plans from them.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <thread>

#include "core/rt/probe.h"
#include "core/rt/profile.h"
#include "tests/support/test_util.h"

namespace enact::rt {
namespace {

// a machine that wakes a sleeping thread `late_us` late at p99 (normal and FIFO alike)
MachineProbe machine(double late_us) {
  MachineProbe p;
  p.cpus = 2;
  p.fifo_permitted = true;
  p.sleep_late = {static_cast<std::int64_t>(late_us * 800), static_cast<std::int64_t>(late_us * 1000), static_cast<std::int64_t>(late_us * 3000), 1000};
  p.sleep_late_fifo = p.sleep_late;
  p.pipe_same_cpu = {14'000, 30'000, 90'000, 2000};
  p.boot_id = "b";
  return p;
}

TEST(MachineProbe, MeasuresEveryFigureOnThisMachine) {
  const MachineProbe p = probe_machine(200'000, 200);
  EXPECT_EQ(p.sleep_late.count, 200);
  EXPECT_LE(p.sleep_late.p50_ns, p.sleep_late.p99_ns);
  EXPECT_LE(p.sleep_late.p99_ns, p.sleep_late.max_ns);
  EXPECT_GE(p.sleep_late.p50_ns, 0);
  // a pipe round trip is two wake-ups: never free
  EXPECT_EQ(p.pipe_same_cpu.count, 2000);
  EXPECT_GT(p.pipe_same_cpu.p50_ns, 0);
  EXPECT_EQ(p.pipe_cross_cpu.count > 0, p.cpus >= 2);
  EXPECT_EQ(p.fifo_permitted, p.sleep_late_fifo.count == 200);
  EXPECT_GT(p.cpus, 0);
  EXPECT_FALSE(p.boot_id.empty());
  // the spinning floor: 5 rounds of at least 4,400 deadlines at 44 kHz (a late last wake-up
  // skips past the round's end), a share of them missed
  EXPECT_GE(p.spin_deadlines, 5 * 4400);
  EXPECT_GE(p.spin_missed_44k, 0.0);
  EXPECT_LE(p.spin_missed_44k, 1.0);
  EXPECT_GE(p.spin_longest_late_ns, 0);
  EXPECT_EQ(p.spin_cpu, system_calls().allowed_cpus().back());
  std::printf("[ measure ] %s", describe(p).c_str());
}

TEST(MachineProbe, TheSpinningFloorSeesACpuTakenAway) {
  // a thread spinning beside the probe on its CPU, at the same priority, takes half of it: the
  // probe then misses many of its 44 kHz deadlines, which the floor is there to tell
  const int cpu = system_calls().allowed_cpus().back();
  MachineProbe quiet;
  measure_spin_floor(cpu, quiet);
  ASSERT_GE(quiet.spin_missed_44k, 0.0) << "CPU " << cpu << " could not be pinned";
  std::atomic<bool> stop{false};
  std::thread hog([&] {
    system_calls().pin_thread({cpu});
    while (!stop.load(std::memory_order_relaxed)) {
    }
  });
  MachineProbe shared;
  measure_spin_floor(cpu, shared);
  stop.store(true);
  hog.join();
  std::printf("[ measure ] the spinning floor alone %.3f %%, beside a thread spinning on its CPU %.3f %%\n", 100.0 * quiet.spin_missed_44k,
              100.0 * shared.spin_missed_44k);
  EXPECT_GT(shared.spin_missed_44k, 0.2);
  EXPECT_GT(shared.spin_missed_44k, quiet.spin_missed_44k);
}

TEST(MachineProbe, ItsTextFormReadsBackWholeAndRefusesAnythingLess) {
  MachineProbe p = machine(41.0);
  p.pipe_cross_cpu = {83'000, 120'000, 400'000, 1000};
  p.rt_runtime_us = 950000;
  p.rt_period_us = 1000000;
  p.default_timer_slack_ns = 50000;
  p.spin_missed_44k = 0.0184;
  p.spin_longest_late_ns = 2'116'900;
  p.spin_deadlines = 22000;
  p.spin_cpu = 3;
  const std::string text = to_text(p);
  const auto back = from_text(text);
  ASSERT_TRUE(back);
  EXPECT_EQ(to_text(*back), text);
  EXPECT_EQ(back->sleep_late.p99_ns, 41'000);
  EXPECT_EQ(back->pipe_cross_cpu.p50_ns, 83'000);
  EXPECT_DOUBLE_EQ(back->spin_missed_44k, 0.0184);
  EXPECT_EQ(back->spin_longest_late_ns, 2'116'900);
  EXPECT_EQ(back->spin_cpu, 3);
  EXPECT_NE(describe(*back).find("on CPU 3,"), std::string::npos) << describe(*back);
  // a file cut short, another format, or nothing at all is measured again
  EXPECT_FALSE(from_text(text.substr(0, text.size() / 2)));
  EXPECT_FALSE(from_text("enact_probe 0\n" + text.substr(text.find('\n') + 1)));
  EXPECT_FALSE(from_text(""));
}

TEST(MachineProbe, IsCachedPerBootAndMeasuredAgainForAnother) {
  test::TempDir dir;
  setenv("XDG_CACHE_HOME", dir.path().c_str(), 1);
  // a cache left by another boot, with figures no machine gives
  MachineProbe old = machine(123'456.0);
  old.boot_id = "another-boot";
  std::filesystem::create_directories(dir.path() + "/enact");
  test::write_file(dir.path() + "/enact/machine-probe", to_text(old));
  const MachineProbe now = cached_probe();
  EXPECT_NE(now.boot_id, "another-boot");
  EXPECT_LT(now.sleep_late.p99_ns, old.sleep_late.p99_ns);
  // this boot's is read back as stored, not measured again
  const MachineProbe again = cached_probe();
  EXPECT_EQ(to_text(again), to_text(now));
  EXPECT_EQ(test::read_file(dir.path() + "/enact/machine-probe"), to_text(now));
  // unless asked
  EXPECT_NE(cached_probe(true).probed_at_ns, 0);
  unsetenv("XDG_CACHE_HOME");
}

// a probe measured on a busy machine is kept for a while, then measured again: a burst of load
// does not decide how every later loop of the boot waits; a quiet machine's is kept
TEST(MachineProbe, OneMeasuredUnderLoadIsMeasuredAgainOnceOld) {
  test::TempDir dir;
  setenv("XDG_CACHE_HOME", dir.path().c_str(), 1);
  const std::string file = dir.path() + "/enact/machine-probe";
  std::filesystem::create_directories(dir.path() + "/enact");
  const std::int64_t now_ns = static_cast<std::int64_t>(std::time(nullptr)) * 1'000'000'000;
  // this boot's, with figures no machine gives, so a probe measured again is told apart
  MachineProbe cached = cached_probe(true);
  cached.sleep_late.p99_ns = 123'456'000;
  auto stored = [&](double load_per_cpu, std::int64_t age_ns) {
    cached.load_per_cpu = load_per_cpu;
    cached.probed_at_ns = now_ns - age_ns;
    test::write_file(file, to_text(cached));
    return cached_probe().sleep_late.p99_ns == cached.sleep_late.p99_ns;
  };
  EXPECT_TRUE(stored(0.5, 2 * kBusyProbeLife_ns)) << "a quiet machine's probe is kept for the boot";
  EXPECT_TRUE(stored(4.0, kBusyProbeLife_ns / 10)) << "a busy machine's, for a while";
  EXPECT_FALSE(stored(4.0, 2 * kBusyProbeLife_ns)) << "then measured again";
  unsetenv("XDG_CACHE_HOME");
}

TEST(WaitPlan, TheSpinWindowCoversThisMachinesLateness) {
  // 41 us late at p99: the window is that plus a quarter plus 5 us, whatever the habit
  const WaitPlan slow = plan_wait(machine(41.0), 200'000, false, true, false);
  EXPECT_FALSE(slow.spin_whole_period);
  EXPECT_EQ(slow.spin_ns, 41'000 + 10'250 + 5'000);
  EXPECT_NE(slow.why.find("41.0 us late"), std::string::npos) << slow.why;
  // a machine that wakes on time spins little
  const WaitPlan quick = plan_wait(machine(3.0), 200'000, false, true, false);
  EXPECT_EQ(quick.spin_ns, 3'000 + 750 + 5'000);
}

TEST(WaitPlan, APeriodShorterThanTwiceTheLatenessIsSpunWholeOnACpuOfItsOwn) {
  // 44 kHz (22.7 us) on a machine 41 us late: a sleep would miss the tick it sleeps for
  const WaitPlan p = plan_wait(machine(41.0), 22'727, false, false, true);
  EXPECT_TRUE(p.spin_whole_period);
  EXPECT_GE(p.spin_ns, 22'727);
  EXPECT_NE(p.why.find("spins the whole"), std::string::npos) << p.why;
  EXPECT_EQ(p.spin_floor, -1.0);  // the machine above measured none
  MachineProbe floored = machine(41.0);
  floored.spin_missed_44k = 0.0184;
  EXPECT_EQ(plan_wait(floored, 22'727, false, false, true).spin_floor, 0.0184);
  // the same rate on a machine that wakes 3 us late sleeps
  EXPECT_FALSE(plan_wait(machine(3.0), 22'727, false, false, true).spin_whole_period);
  // without a CPU of its own, or when it must sleep (FIFO, a shared CPU), it never spins whole
  EXPECT_FALSE(plan_wait(machine(41.0), 22'727, false, false, false).spin_whole_period);
  const WaitPlan shared = plan_wait(machine(41.0), 22'727, true, true, true);
  EXPECT_FALSE(shared.spin_whole_period);
  EXPECT_EQ(shared.spin_ns, 22'727 / 2);
  EXPECT_NE(shared.why.find("some ticks will be late"), std::string::npos) << shared.why;
}

TEST(WaitPlan, FifoUsesTheLatenessMeasuredUnderFifo) {
  MachineProbe p = machine(41.0);
  p.sleep_late_fifo.p99_ns = 8'000;
  EXPECT_EQ(plan_wait(p, 200'000, true, true, false).spin_ns, 8'000 + 2'000 + 5'000);
  p.fifo_permitted = false;  // refused: the normal figure holds
  EXPECT_EQ(plan_wait(p, 200'000, true, true, false).spin_ns, 41'000 + 10'250 + 5'000);
}

TEST(WaitPlan, TheSleepingRateLimitFollowsTheLateness) {
  EXPECT_NEAR(sleeping_rate_limit_hz(machine(41.0), false, 2'000), 1e9 / (2.0 * 56'250 + 2'000), 1e-6);
  EXPECT_DOUBLE_EQ(sleeping_rate_limit_hz(machine(0.0), false, 0), 44'000.0);
}

TEST(WaitPlan, ASpinWindowSetByHandIsKeptAndSaidSo) {
  const WaitPlan p = loop_wait(50.0, 200'000, false, true, false);
  EXPECT_EQ(p.spin_ns, 50'000);
  EXPECT_FALSE(p.spin_whole_period);
  EXPECT_NE(p.why.find("by hand"), std::string::npos);
}

}  // namespace
}  // namespace enact::rt
