// The periodic scheduler: parameter validation, drift-free deadlines, wake-up order,
// overrun accounting (missed deadlines skipped, not caught up), no allocation. No timing
// assertions: the machine is shared and noisy.
#include "core/rt/scheduler.h"

#include <gtest/gtest.h>
#include <poll.h>

#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "core/config/yaml.h"
#include "core/rt/clock.h"
#include "tests/support/alloc_guard.h"
#include "tests/support/refusal.h"

namespace enact::rt {
namespace {

// the message of the config::Error thrown by building a scheduler with these params
std::string error_of(SchedulerParams params) {
  return test::error_of([&] { PeriodicScheduler s(params); });
}

TEST(SchedulerParams, RateOutOfRangeNamesTheFieldAndTheFix) {
  for (const double rate : {0.0, 0.5, 44'001.0, -5000.0, std::nan("")}) {
    const std::string msg = error_of({.rate_hz = rate});
    EXPECT_NE(msg.find("rate_hz"), std::string::npos) << msg;
    EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
  }
  EXPECT_EQ(error_of({.rate_hz = 1.0}), "");
  EXPECT_EQ(error_of({.rate_hz = 44'000.0}), "");
}

TEST(SchedulerParams, NegativeSpinNamesTheFieldAndTheFix) {
  const std::string msg = error_of({.spin_ns = -1});
  EXPECT_NE(msg.find("spin_ns"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fix:"), std::string::npos) << msg;
  EXPECT_EQ(error_of({.spin_ns = 0}), "");
}

TEST(PeriodicScheduler, DeadlinesAreDriftFree) {
  PeriodicScheduler s({.rate_hz = 3000.0});
  const std::int64_t first = 1'000'000'007;
  s.start(first);
  EXPECT_EQ(s.period_ns(), 333'333);
  EXPECT_EQ(s.deadline_at(0), first);
  EXPECT_EQ(s.deadline_at(1), first + 333'333);
  EXPECT_EQ(s.deadline_at(3), first + 1'000'000);
  EXPECT_EQ(s.deadline_at(3000), first + 1'000'000'000);
  // a day later, still exact
  EXPECT_EQ(s.deadline_at(3000LL * 86'400), first + 86'400LL * 1'000'000'000);
  // a rate that is not a whole number of hertz
  PeriodicScheduler odd({.rate_hz = 4999.5});
  odd.start(0);
  EXPECT_EQ(odd.deadline_at(9999), 2'000'000'000);
  EXPECT_EQ(odd.deadline_at(1), 200'020);
}

TEST(PeriodicScheduler, TwoHundredTicksAtFiveKilohertz) {
  PeriodicScheduler s({.rate_hz = 5000.0});
  EXPECT_EQ(s.period_ns(), 200'000);
  const std::int64_t first = now_ns() + 1'000'000;
  s.start(first);
  std::vector<std::int64_t> woke, deadlines, indices;
  for (int n = 0; n < 200; ++n) {
    woke.push_back(s.wait());
    deadlines.push_back(s.deadline_ns());
    indices.push_back(s.deadline_index());
  }
  ASSERT_EQ(woke.size(), 200u);
  EXPECT_EQ(s.ticks(), 200u);
  EXPECT_EQ(s.jitter().count(), 200u);
  for (std::size_t n = 0; n < woke.size(); ++n) {
    // never before its deadline; deadlines on the exact grid; indices only move forward
    EXPECT_GE(woke[n], deadlines[n]);
    EXPECT_EQ(deadlines[n], first + indices[n] * 200'000);
    if (n == 0) continue;
    EXPECT_GE(woke[n], woke[n - 1]);
    EXPECT_GT(indices[n], indices[n - 1]);
  }
  // every index not woken for was skipped by an overrun (normally none on a quiet machine)
  EXPECT_EQ(static_cast<std::uint64_t>(indices.back() + 1), s.ticks() + s.skipped());
  EXPECT_EQ(s.overruns() > 0, s.skipped() > 0);
}

TEST(PeriodicScheduler, EverySkippedDeadlineCountsAsAnOverrun) {
  PeriodicScheduler s({.rate_hz = 5000.0});
  // the first deadline lies ten periods in the past: the wake-up is late and at least the
  // nine deadlines after it already passed
  s.start(now_ns() - 10 * s.period_ns());
  s.wait();
  EXPECT_EQ(s.ticks(), 1u);
  EXPECT_GE(s.skipped(), 9u);
  EXPECT_EQ(s.overruns(), 1 + s.skipped());
}

// whether fd is readable within timeout_ms
bool readable(int fd, int timeout_ms) {
  pollfd p{fd, POLLIN, 0};
  return poll(&p, 1, timeout_ms) == 1;
}

TEST(PeriodicScheduler, ItsWakeTimerIsReadableWhenTheNextSleepEndsAndTheDeadlinesStayTheSame) {
  // 100 Hz, a 2 ms spin window: the next sleep ends 8 ms after a tick
  PeriodicScheduler s({.rate_hz = 100.0, .spin_ns = 2'000'000, .wake_fd = true});
  PeriodicScheduler plain({.rate_hz = 100.0, .spin_ns = 2'000'000});
  const std::int64_t first = now_ns() + 5'000'000;
  s.start(first);
  plain.start(first);
  for (int tick = 0; tick < 5; ++tick) {
    const std::int64_t woke = s.wait();
    ASSERT_GE(woke, s.deadline_ns());  // never before its deadline
    // on the plain scheduler's grid; a tick the machine held past a whole period (a loaded CI
    // machine did, once) skips deadlines as the plain one does
    ASSERT_EQ(s.deadline_ns(), first + (tick + static_cast<std::int64_t>(s.skipped())) * 10'000'000);
    const std::int64_t ends = s.next_deadline_ns() - s.spin_ns();
    const int fd = s.reply_wait(ends).stop_fd;
    ASSERT_GE(fd, 0) << "armed for the next sleep's end while the tick spun";
    EXPECT_EQ(s.reply_wait(ends).until, ends + PeriodicScheduler::kReplyBackstop_ns);  // the timer ends it: a far backstop
    EXPECT_EQ(s.reply_wait(ends + 1).stop_fd, -1);
    EXPECT_EQ(s.reply_wait(ends + 1).until, ends + 1);
    // not before its time (a tick takes far less than 8 ms here), then at it
    if (now_ns() + 1'000'000 < ends) EXPECT_FALSE(readable(fd, 0));
    ASSERT_TRUE(readable(fd, 1000));
    EXPECT_GE(now_ns(), ends);
  }
  // a late tick: the deadlines passed are skipped as without the timer, and the timer is
  // armed for the sleep before the first deadline still ahead, not the one skipped
  sleep_until_ns(now_ns() + 35'000'000);
  s.wait();
  EXPECT_GE(s.skipped(), 2u);
  EXPECT_GE(s.reply_wait(s.next_deadline_ns() - s.spin_ns()).stop_fd, 0);
  EXPECT_GT(s.next_deadline_ns(), now_ns());
  // what it returns is the plain scheduler's: the same deadlines
  for (std::int64_t n = 0; n < 20; ++n) EXPECT_EQ(s.deadline_at(n), plain.deadline_at(n));
}

TEST(PeriodicScheduler, WithoutAWakeTimerThereIsNoneToWaitOn) {
  PeriodicScheduler s({.rate_hz = 1000.0, .spin_ns = 100'000});
  s.start(now_ns());
  s.wait();
  EXPECT_EQ(s.reply_wait(s.next_deadline_ns() - s.spin_ns()).stop_fd, -1);
  PeriodicScheduler simulated({.rate_hz = 1000.0, .simulated = true, .wake_fd = true});
  simulated.wait();
  EXPECT_EQ(simulated.reply_wait(simulated.next_deadline_ns() - simulated.spin_ns()).stop_fd, -1);
}

TEST(PeriodicScheduler, SimulatedTimeReturnsEveryDeadlineAtOnceAndMissesNone) {
  // deadlines an hour ahead of the clock: a real wait would sleep for an hour; and one in the
  // past would be an overrun with skipped deadlines
  for (const std::int64_t first : {now_ns() + 3'600'000'000'000, now_ns() - 1'000'000'000}) {
    PeriodicScheduler s({.rate_hz = 3000.0, .simulated = true});
    s.start(first);
    for (std::int64_t n = 0; n < 3001; ++n) ASSERT_EQ(s.wait(), s.deadline_at(n));
    EXPECT_EQ(s.wait() - first, 1'000'333'333);  // tick 3001: 1 s + 1/3000 s, drift-free
    EXPECT_EQ(s.ticks(), 3002u);
    EXPECT_EQ(s.overruns(), 0u);
    EXPECT_EQ(s.skipped(), 0u);
  }
}

TEST(PeriodicScheduler, SleepEveryTickCapsTheSpinAtHalfAPeriod) {
  // 44 kHz: a 50 us spin window is longer than the period, so the loop would never sleep
  EXPECT_EQ(PeriodicScheduler({.rate_hz = 44000.0, .spin_ns = 50'000}).spin_ns(), 50'000);
  const PeriodicScheduler capped({.rate_hz = 44000.0, .spin_ns = 50'000, .sleep_every_tick = true});
  EXPECT_EQ(capped.spin_ns(), capped.period_ns() / 2);
  EXPECT_EQ(PeriodicScheduler({.rate_hz = 5000.0, .spin_ns = 50'000, .sleep_every_tick = true}).spin_ns(), 50'000);
}

TEST(PeriodicScheduler, SleepLatenessIsMeasuredBeforeTheSpin) {
  PeriodicScheduler s({.rate_hz = 1000.0, .spin_ns = 100'000});
  s.start(now_ns() + 2'000'000);
  s.wait();
  // it slept (the deadline was 2 ms ahead): lateness from the end of the sleep, never negative
  EXPECT_GE(s.last_sleep_late_ns(), 0);
  // inside the spin window already: no sleep
  s.start(now_ns() + 50'000);
  s.wait();
  EXPECT_EQ(s.last_sleep_late_ns(), -1);
}

TEST(PeriodicScheduler, AStallIsAnOverrunAndMissedDeadlinesAreSkipped) {
  PeriodicScheduler s({.rate_hz = 5000.0});
  s.start(now_ns() + 1'000'000);
  for (int n = 0; n < 5; ++n) s.wait();
  const std::uint64_t overruns_before = s.overruns();
  const std::uint64_t skipped_before = s.skipped();
  // the loop body stalls for three periods once
  std::this_thread::sleep_for(std::chrono::nanoseconds(3 * s.period_ns()));
  const std::int64_t woke = s.wait();
  EXPECT_GE(s.overruns(), overruns_before + 1);
  // at least the two deadlines passed during the stall were skipped, not run back to back
  EXPECT_GE(s.skipped(), skipped_before + 2);
  EXPECT_GT(s.next_deadline_ns(), woke);
  EXPECT_EQ(s.next_deadline_ns(), s.deadline_at(s.deadline_index() + 1 + static_cast<std::int64_t>(s.skipped() - skipped_before)));
  // the loop goes on, on the same grid
  const std::int64_t next = s.wait();
  EXPECT_GE(next, s.deadline_ns());
  EXPECT_EQ((s.deadline_ns() - s.deadline_at(0)) % s.period_ns(), 0);
}

TEST(PeriodicScheduler, WaitBeforeStartStartsNow) {
  PeriodicScheduler s({.rate_hz = 1000.0, .spin_ns = 0});
  const std::int64_t before = now_ns();
  const std::int64_t woke = s.wait();
  EXPECT_GE(woke, before);
  EXPECT_EQ(s.ticks(), 1u);
}

TEST(PeriodicScheduler, WaitAllocatesNothing) {
  PeriodicScheduler s({.rate_hz = 5000.0});
  s.start(now_ns() + 1'000'000);
  std::vector<int> v;
  std::size_t wait_allocations = 0, vector_allocations = 0;
  {
    enact::test::AllocGuard guard;
    for (int n = 0; n < 100; ++n) s.wait();
    // an overrun takes the skipping path too
    std::this_thread::sleep_for(std::chrono::nanoseconds(3 * s.period_ns()));
    s.wait();
    wait_allocations = guard.allocations();
    v.push_back(1);
    vector_allocations = guard.allocations() - wait_allocations;
  }
  EXPECT_EQ(wait_allocations, 0u);
  EXPECT_GT(vector_allocations, 0u);
  EXPECT_GE(s.overruns(), 1u);
}

}  // namespace
}  // namespace enact::rt
