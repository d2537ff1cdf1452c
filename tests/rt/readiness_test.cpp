// What `enact doctor` decides, in process: the machine's checks and the rates each mode of the
// loop holds given the probe's figures.
#include "core/rt/readiness.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace enact::rt {
namespace {

// a machine whose sleeping thread wakes late_us late at p99, with a pipe round trip of 5 us
MachineProbe machine(double late_us, int cpus = 2) {
  MachineProbe p;
  p.cpus = cpus;
  p.sleep_late = {static_cast<std::int64_t>(late_us * 500), static_cast<std::int64_t>(late_us * 1000), static_cast<std::int64_t>(late_us * 2000), 1000};
  p.pipe_same_cpu = {4'000, 5'000, 20'000, 1000};
  return p;
}

TEST(Readiness, EveryCheckHasANameALevelAndWhatWasFound) {
  const std::vector<Check> checks = machine_checks();
  ASSERT_EQ(checks.size(), 12u);
  std::set<std::string> names;
  for (const Check& c : checks) {
    EXPECT_FALSE(c.found.empty()) << c.name;
    EXPECT_TRUE(names.insert(c.name).second) << c.name << " twice";
    // what is not ok says how to fix it
    if (c.level != Level::ok) {
      EXPECT_NE(c.found.find("fix"), std::string::npos) << c.name << ": " << c.found;
    }
  }
}

TEST(Readiness, ALaterWakeUpHoldsALowerRateAndOneCpuNeverSpins) {
  constexpr std::int64_t kTick_ns = 1'000;
  const HeldRates quick = held_rates(machine(10.0), kTick_ns), slow = held_rates(machine(80.0), kTick_ns);
  EXPECT_GT(quick.sleeping_hz, slow.sleeping_hz);
  EXPECT_GT(quick.distributed_hz, slow.distributed_hz);
  // spinning does not wait on a wake-up: the same on both, capped at 44 kHz
  EXPECT_EQ(quick.spinning_hz, slow.spinning_hz);
  EXPECT_LE(quick.spinning_hz, 44'000.0);
  EXPECT_GT(quick.spinning_hz, 0.0);
  // the distributed hop cannot beat its window and round trip: 80 us late, 5 us pipe, 1 us step
  EXPECT_LE(slow.distributed_hz, 1e9 / (80'000.0 + 5'000.0 + 1'000.0));
  EXPECT_EQ(held_rates(machine(10.0, 1), kTick_ns).spinning_hz, 0.0);
}

}  // namespace
}  // namespace enact::rt
