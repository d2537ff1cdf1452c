// Real-time setup: invalid params throw, defaults do nothing, and SCHED_FIFO, memory locking
// and pinning are either granted (and really in effect) or refused with a note giving the
// fix, never thrown. Each request runs on a scratch thread, so the scheduling and affinity
// of the test thread are never changed; memory is unlocked afterwards.
#include "core/rt/rt_setup.h"

#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <string>
#include <thread>

#include "core/config/yaml.h"

namespace enact::rt {
namespace {

// what the scratch thread saw after applying the request
struct Applied {
  RtReport report;
  int policy = -1;
  int priority = -1;
  int cpu = -1;
  std::size_t prefaulted = 0;
};

Applied apply_on_scratch_thread(const RtParams& params) {
  Applied a;
  std::thread t([&] {
    a.report = apply_rt_setup(params);
    sched_param sp{};
    pthread_getschedparam(pthread_self(), &a.policy, &sp);
    a.priority = sp.sched_priority;
    a.cpu = sched_getcpu();
    a.prefaulted = prefault_stack();
    // back to normal scheduling before the thread ends
    sched_param normal{};
    pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal);
  });
  t.join();
  munlockall();
  return a;
}

// every refused request says how to get it
bool refusals_have_a_fix(const RtReport& r) {
  for (const std::string& n : r.notes) {
    if (n.find("refused") != std::string::npos && n.find("fix:") == std::string::npos) return false;
  }
  return true;
}

RtParams fifo(int priority, bool lock_memory = false) {
  RtParams p;
  p.fifo_priority = priority;
  p.lock_memory = lock_memory;
  return p;
}

TEST(RtSetup, InvalidParamsThrowConfigError) {
  EXPECT_THROW(apply_rt_setup(fifo(-1)), config::Error);
  EXPECT_THROW(apply_rt_setup(fifo(100)), config::Error);
  EXPECT_THROW(apply_rt_setup({.cpus = {0, -1}}), config::Error);
  try {
    apply_rt_setup(fifo(100));
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("fifo_priority"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("fix:"), std::string::npos) << e.what();
  }
}

TEST(RtSetup, DefaultsDoNothing) {
  const Applied a = apply_on_scratch_thread({});
  EXPECT_FALSE(a.report.memory_locked);
  EXPECT_FALSE(a.report.fifo);
  EXPECT_FALSE(a.report.pinned);
  EXPECT_TRUE(a.report.notes.empty());
  EXPECT_EQ(a.report.summary(), "no real-time setup requested");
  EXPECT_EQ(a.policy, SCHED_OTHER);
}

TEST(RtSetup, FifoAndMemoryLockAreGrantedOrRefusedWithAFix) {
  Applied a;
  ASSERT_NO_THROW(a = apply_on_scratch_thread(fifo(10, true)));
  ASSERT_EQ(a.report.notes.size(), 2u) << a.report.summary();
  EXPECT_TRUE(refusals_have_a_fix(a.report)) << a.report.summary();
  if (a.report.fifo) {
    EXPECT_EQ(a.policy, SCHED_FIFO);
    EXPECT_EQ(a.priority, 10);
  } else {
    EXPECT_NE(a.report.notes[1].find("SCHED_FIFO refused"), std::string::npos) << a.report.summary();
    EXPECT_EQ(a.policy, SCHED_OTHER);
  }
  if (!a.report.memory_locked) {
    EXPECT_NE(a.report.notes[0].find("fix:"), std::string::npos) << a.report.summary();
  }
  EXPECT_GT(a.prefaulted, 0u);
  RecordProperty("rt_setup", a.report.summary());
}

TEST(RtSetup, PinningToCpuZeroWorksOrReports) {
  const Applied a = apply_on_scratch_thread({.cpus = {0}});
  ASSERT_EQ(a.report.notes.size(), 1u);
  if (a.report.pinned) {
    EXPECT_EQ(a.cpu, 0);
  } else {
    EXPECT_NE(a.report.notes[0].find("fix:"), std::string::npos) << a.report.summary();
  }
}

TEST(RtSetup, PinningToAMissingCpuIsRefusedNotThrown) {
  Applied a;
  ASSERT_NO_THROW(a = apply_on_scratch_thread({.cpus = {CPU_SETSIZE - 1}}));
  EXPECT_FALSE(a.report.pinned);
  ASSERT_EQ(a.report.notes.size(), 1u);
  EXPECT_NE(a.report.notes[0].find("refused"), std::string::npos) << a.report.summary();
  EXPECT_NE(a.report.notes[0].find("fix:"), std::string::npos) << a.report.summary();
}

TEST(RtSetup, PrefaultStopsShortOfTheStackEnd) {
  // far more than any thread's stack: clamped, not a crash
  std::size_t touched = 0;
  std::thread t([&] { touched = prefault_stack(std::size_t{1} << 40); });
  t.join();
  EXPECT_GT(touched, 0u);
  EXPECT_LT(touched, std::size_t{1} << 40);
}

}  // namespace
}  // namespace enact::rt
