#include "core/task/bridge_task.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

using enact::task::BridgeTask;
using enact::task::TaskEvent;
using enact::task::TaskEventKind;
using enact::task::TaskParams;

namespace {

constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kSample = 200'000;  // 5 kHz
constexpr double kSample_s = 200e-6;

std::int64_t ms(std::int64_t milliseconds) { return milliseconds * 1'000'000; }

// an event as returned by update(), with the time of the sample that reported it
struct Reported {
  TaskEvent event;
  std::int64_t at_ns;
};

// feeds one sample every 200 us over [from_ns, to_ns) with a constant contact and progress
std::vector<Reported> feed(BridgeTask& task, std::int64_t from_ns, std::int64_t to_ns, bool on_top,
                           double progress = 0.5) {
  std::vector<Reported> events;
  for (std::int64_t t = from_ns; t < to_ns; t += kSample) {
    const TaskEvent event = task.update(t, on_top, progress);
    if (event.kind != TaskEventKind::none) events.push_back({event, t});
  }
  return events;
}

// appends b to a
void append(std::vector<Reported>& a, const std::vector<Reported>& b) { a.insert(a.end(), b.begin(), b.end()); }

}  // namespace

TEST(BridgeTask, LossOf900msIsNotAFall) {
  BridgeTask task;
  task.reset(0);
  auto events = feed(task, 0, ms(1000), true);
  append(events, feed(task, ms(1000), ms(1900), false));
  append(events, feed(task, ms(1900), ms(4000), true));

  EXPECT_TRUE(events.empty());
  EXPECT_FALSE(task.falling());
  const auto m = task.metrics();
  EXPECT_EQ(m.falls, 0);
  EXPECT_EQ(m.time_out_s, 0.0);
  EXPECT_NEAR(m.time_total_s, 4.0 - kSample_s, 1e-9);
}

TEST(BridgeTask, LossOneSampleShortOfOneSecondIsNotAFall) {
  BridgeTask task;
  task.reset(0);
  feed(task, 0, ms(1000), true);
  feed(task, ms(1000), ms(2000) - kSample, false);
  const auto events = feed(task, ms(2000) - kSample, ms(5000), true);

  EXPECT_TRUE(events.empty());
  EXPECT_EQ(task.metrics().falls, 0);
}

TEST(BridgeTask, LossOfOneSecondIsAFallThatBeganWhenContactWasLost) {
  BridgeTask task;
  task.reset(0);
  auto events = feed(task, 0, ms(1000), true);
  append(events, feed(task, ms(1000), ms(2000), false));
  append(events, feed(task, ms(2000), ms(4000), true));

  // known at 2.0 s, dated 1.0 s; ended when contact came back, known 1 s later
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].event.kind, TaskEventKind::fall_start);
  EXPECT_EQ(events[0].event.time_ns, ms(1000));
  EXPECT_EQ(events[0].at_ns, ms(2000));
  EXPECT_EQ(events[1].event.kind, TaskEventKind::fall_end);
  EXPECT_EQ(events[1].event.time_ns, ms(2000));
  EXPECT_EQ(events[1].at_ns, ms(3000));

  const auto m = task.metrics();
  EXPECT_EQ(m.falls, 1);
  EXPECT_NEAR(m.time_out_s, 1.0, kSample_s);
  EXPECT_FALSE(task.falling());
}

TEST(BridgeTask, FallIsCountedWhileStillOffAtOneSecond) {
  BridgeTask task;
  task.reset(0);
  feed(task, 0, ms(500), true);
  const auto before = feed(task, ms(500), ms(1500), false);
  EXPECT_TRUE(before.empty());
  EXPECT_FALSE(task.falling());

  const TaskEvent event = task.update(ms(1500), false, 0.5);
  EXPECT_EQ(event.kind, TaskEventKind::fall_start);
  EXPECT_EQ(event.time_ns, ms(500));
  EXPECT_TRUE(task.falling());
  EXPECT_EQ(task.metrics().falls, 1);
}

TEST(BridgeTask, ContactRegainedForHalfASecondDoesNotEndTheFall) {
  BridgeTask task;
  task.reset(0);
  auto events = feed(task, 0, ms(1000), true);
  append(events, feed(task, ms(1000), ms(3000), false));
  append(events, feed(task, ms(3000), ms(3500), true));  // brief contact inside the fall
  append(events, feed(task, ms(3500), ms(5000), false));
  append(events, feed(task, ms(5000), ms(7000), true));

  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].event.kind, TaskEventKind::fall_start);
  EXPECT_EQ(events[0].event.time_ns, ms(1000));
  EXPECT_EQ(events[1].event.kind, TaskEventKind::fall_end);
  EXPECT_EQ(events[1].event.time_ns, ms(5000));
  EXPECT_EQ(events[1].at_ns, ms(6000));

  // one fall from 1 s to 5 s, the half second of contact included
  const auto m = task.metrics();
  EXPECT_EQ(m.falls, 1);
  EXPECT_NEAR(m.time_out_s, 4.0, kSample_s);
  EXPECT_NEAR(m.time_total_s, 7.0, kSample_s);
  EXPECT_NEAR(m.ratio, 4.0 / 7.0, 1e-4);
}

TEST(BridgeTask, TwoFallsAddTheirTimeOut) {
  BridgeTask task;
  task.reset(0);
  feed(task, 0, ms(1000), true);
  feed(task, ms(1000), ms(2500), false);  // 1.5 s out
  feed(task, ms(2500), ms(4000), true);
  feed(task, ms(4000), ms(6200), false);  // 2.2 s out
  feed(task, ms(6200), ms(8000), true);
  feed(task, ms(8000), ms(8900), false);  // 0.9 s: not a fall
  feed(task, ms(8900), ms(10000), true);

  const auto m = task.metrics();
  EXPECT_EQ(m.falls, 2);
  EXPECT_NEAR(m.time_out_s, 3.7, kSample_s);
  EXPECT_NEAR(m.time_total_s, 10.0, kSample_s);
  EXPECT_NEAR(m.ratio, 0.37, 1e-4);
}

TEST(BridgeTask, OpenFallCountsUpToTheLastSample) {
  BridgeTask task;
  task.reset(0);
  feed(task, 0, ms(1000), true);
  feed(task, ms(1000), ms(3000) + kSample, false);  // last sample at 3.0 s

  EXPECT_TRUE(task.falling());
  const auto m = task.metrics();
  EXPECT_EQ(m.falls, 1);
  EXPECT_NEAR(m.time_out_s, 2.0, kSample_s);
  EXPECT_NEAR(m.time_total_s, 3.0, kSample_s);
  EXPECT_NEAR(m.ratio, 2.0 / 3.0, 1e-4);
}

TEST(BridgeTask, PendingRecoveryAtTheEndStillCountsAsTimeOut) {
  BridgeTask task;
  task.reset(0);
  feed(task, 0, ms(1000), true);
  feed(task, ms(1000), ms(2500), false);
  feed(task, ms(2500), ms(3000) + kSample, true);  // back on for 0.5 s, last sample at 3.0 s

  EXPECT_TRUE(task.falling());
  const auto m = task.metrics();
  EXPECT_EQ(m.falls, 1);
  EXPECT_NEAR(m.time_out_s, 2.0, kSample_s);
}

TEST(BridgeTask, ShortLossAtTheEndIsNotAFall) {
  BridgeTask task;
  task.reset(0);
  feed(task, 0, ms(1000), true);
  feed(task, ms(1000), ms(1500) + kSample, false);

  EXPECT_FALSE(task.falling());
  const auto m = task.metrics();
  EXPECT_EQ(m.falls, 0);
  EXPECT_EQ(m.time_out_s, 0.0);
  EXPECT_NEAR(m.time_total_s, 1.5, kSample_s);
}

TEST(BridgeTask, CompletionStopsTheClock) {
  BridgeTask task;
  task.reset(ms(500));
  std::vector<Reported> events;
  // progress ramps from 0 to 1 over 2 s on top, reaching 0.98 at 2.46 s
  for (std::int64_t t = ms(500); t < ms(3000); t += kSample) {
    const double progress = static_cast<double>(t - ms(500)) / static_cast<double>(2 * kSecond);
    const TaskEvent event = task.update(t, true, progress);
    if (event.kind != TaskEventKind::none) events.push_back({event, t});
  }
  // later samples change nothing, falls included
  append(events, feed(task, ms(3000), ms(6000), false, 0.1));

  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].event.kind, TaskEventKind::completed);
  EXPECT_EQ(events[0].event.time_ns, ms(2460));
  const auto m = task.metrics();
  EXPECT_TRUE(m.completed);
  EXPECT_NEAR(m.time_total_s, 1.96, kSample_s);
  EXPECT_EQ(m.falls, 0);
  EXPECT_EQ(m.time_out_s, 0.0);
  EXPECT_NEAR(m.progress, 0.98, 1e-3);
  EXPECT_FALSE(task.falling());
}

TEST(BridgeTask, CompletionRequiresContact) {
  BridgeTask task;
  task.reset(0);
  const auto events = feed(task, 0, ms(500), false, 1.0);
  EXPECT_TRUE(events.empty());
  EXPECT_FALSE(task.metrics().completed);
  EXPECT_EQ(task.metrics().progress, 0.0);  // progress off the top is not progress
}

TEST(BridgeTask, CompletionClosesAnOpenFall) {
  BridgeTask task;
  task.reset(0);
  feed(task, 0, ms(1000), true, 0.9);
  feed(task, ms(1000), ms(2500), false, 0.9);
  feed(task, ms(2500), ms(3000), true, 0.9);  // regained, not yet for 1 s
  EXPECT_TRUE(task.falling());

  const TaskEvent event = task.update(ms(3000), true, 0.99);
  EXPECT_EQ(event.kind, TaskEventKind::completed);
  EXPECT_EQ(event.time_ns, ms(3000));
  EXPECT_FALSE(task.falling());
  feed(task, ms(3000) + kSample, ms(5000), false);

  const auto m = task.metrics();
  EXPECT_EQ(m.falls, 1);
  EXPECT_NEAR(m.time_out_s, 2.0, kSample_s);
  EXPECT_NEAR(m.time_total_s, 3.0, kSample_s);
  EXPECT_NEAR(m.ratio, 2.0 / 3.0, 1e-4);
}

TEST(BridgeTask, ProgressIsTheFurthestReachedOnTop) {
  BridgeTask task;
  task.reset(0);
  task.update(ms(1), true, 0.3);
  task.update(ms(2), false, 0.7);  // off the top: ignored
  task.update(ms(3), true, 0.2);   // going back does not lower it
  EXPECT_DOUBLE_EQ(task.metrics().progress, 0.3);
}

TEST(BridgeTask, FirstSampleOffTopStartsTheLossAtThatSample) {
  BridgeTask task;
  task.reset(ms(10'000));
  const auto events = feed(task, ms(10'200), ms(11'400), false);

  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].event.kind, TaskEventKind::fall_start);
  EXPECT_EQ(events[0].event.time_ns, ms(10'200));
  EXPECT_EQ(events[0].at_ns, ms(11'200));
  EXPECT_NEAR(task.metrics().time_total_s, 1.4 - kSample_s, 1e-9);
}

TEST(BridgeTask, ResetForgetsTheLastTrial) {
  BridgeTask task;
  task.reset(0);
  feed(task, 0, ms(3000), false);
  task.update(ms(3000), true, 1.0);
  ASSERT_TRUE(task.metrics().completed);

  task.reset(ms(5000));
  const auto m = task.metrics();
  EXPECT_EQ(m.falls, 0);
  EXPECT_EQ(m.time_total_s, 0.0);
  EXPECT_EQ(m.time_out_s, 0.0);
  EXPECT_EQ(m.ratio, 0.0);
  EXPECT_FALSE(m.completed);
  EXPECT_EQ(m.progress, 0.0);
  EXPECT_FALSE(task.falling());
}

TEST(BridgeTask, ThresholdsComeFromTheParams) {
  BridgeTask task(TaskParams{.min_fall_s = 0.25, .min_recovery_s = 0.5, .end_progress = 0.9});
  task.reset(0);
  feed(task, 0, ms(100), true);
  feed(task, ms(100), ms(400), false);  // 0.3 s >= 0.25 s: a fall
  feed(task, ms(400), ms(800), true);   // 0.4 s < 0.5 s: does not end it
  feed(task, ms(800), ms(900), false);
  feed(task, ms(900), ms(1500), true);  // 0.6 s: ends it at 0.9 s

  const auto m = task.metrics();
  EXPECT_EQ(m.falls, 1);
  EXPECT_NEAR(m.time_out_s, 0.8, kSample_s);
  EXPECT_EQ(task.update(ms(1500), true, 0.9).kind, TaskEventKind::completed);
}

TEST(BridgeTask, OlderSamplesAreIgnored) {
  BridgeTask task;
  task.reset(0);
  feed(task, 0, ms(2000), true);
  EXPECT_EQ(task.update(ms(1000), false, 0.5).kind, TaskEventKind::none);
  EXPECT_NEAR(task.metrics().time_total_s, 2.0, kSample_s);
  EXPECT_FALSE(task.falling());
}

TEST(BridgeTask, InvalidParamsThrow) {
  EXPECT_THROW(BridgeTask(TaskParams{.min_fall_s = -1.0}), std::invalid_argument);
  EXPECT_THROW(BridgeTask(TaskParams{.min_recovery_s = std::nan("")}), std::invalid_argument);
  EXPECT_THROW(BridgeTask(TaskParams{.end_progress = 0.0}), std::invalid_argument);
  EXPECT_THROW(BridgeTask(TaskParams{.end_progress = 1.5}), std::invalid_argument);
}
