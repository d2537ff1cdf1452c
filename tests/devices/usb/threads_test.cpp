// What crosses between a backend's I/O thread and the real-time loop: Latest<T> never hands
// out a torn value (a writer hammering it while readers check an invariant), allocates
// nothing; the I/O thread's start, stop and end; emergency stops run once each, while
// registered.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <thread>

#include "core/devices/usb/emergency.h"
#include "core/devices/usb/io_thread.h"
#include "core/devices/usb/latest.h"
#include "tests/devices/usb_test_util.h"
#include "tests/support/alloc_guard.h"

namespace enact::devices::usb {
namespace {

// every word equal: a value half from one store and half from another breaks it
struct Words {
  std::array<std::uint64_t, 9> w{};
};

TEST(UsbLatest, ReadersNeverSeeATornValue) {
  Latest<Words> latest;
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    Words v;
    for (std::uint64_t i = 1; !stop.load(); ++i) {
      v.w.fill(i);
      latest.store(v);
    }
  });
  std::uint64_t torn = 0, changes = 0, last = 0;
  // read until the writer changed the value many times under the readers. On a loaded machine
  // the two threads may share one CPU and the value changes only when they switch (a few
  // hundred times a second): the bound only keeps a broken program from hanging the suite
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (changes < 1000 && std::chrono::steady_clock::now() < end) {
    const Words v = latest.load();
    for (std::uint64_t x : v.w) torn += x != v.w[0];
    changes += v.w[0] != last;
    last = v.w[0];
  }
  stop = true;
  writer.join();
  EXPECT_EQ(torn, 0u);
  EXPECT_GE(changes, 1000u) << "the writer never overlapped the readers: the check above was vacuous";
}

TEST(UsbLatest, StoreAndLoadAllocateNothing) {
  Latest<Words> latest;
  Words v;
  test::AllocGuard guard;
  for (int i = 0; i < 1000; ++i) {
    v.w[0] = static_cast<std::uint64_t>(i);
    latest.store(v);
    v = latest.load();
  }
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_EQ(latest.version(), 1001u);
}

TEST(UsbIoThread, StepsUntilStoppedOrUntilAStepSaysEnough) {
  IoThread io;
  std::atomic<int> steps{0};
  io.start(100'000, [&](std::int64_t) {
    ++steps;
    return true;
  });
  EXPECT_TRUE(test::eventually([&] { return steps.load() >= 10; }));
  io.stop();
  EXPECT_FALSE(io.running());
  const int after = steps.load();
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(steps.load(), after);
  io.stop();  // twice: fine

  std::atomic<int> left{3};
  io.start(100'000, [&](std::int64_t) { return --left > 0; });
  EXPECT_TRUE(test::eventually([&] { return !io.running(); }));
  EXPECT_EQ(left.load(), 0);
}

std::atomic<int> g_stopped_a{0}, g_stopped_b{0};
void stop_a(void* ctx) noexcept { g_stopped_a += *static_cast<int*>(ctx); }
void stop_b(void*) noexcept { ++g_stopped_b; }

TEST(UsbEmergency, RegisteredStopsRunOncePerCallUntilReleased) {
  int weight = 2;
  {
    EmergencyStop a(stop_a, &weight);
    EmergencyStop b(stop_b, nullptr);
    run_emergency_stops();
    EXPECT_EQ(g_stopped_a.load(), 2);
    EXPECT_EQ(g_stopped_b.load(), 1);
    b.reset();
    EXPECT_FALSE(b.armed());
    run_emergency_stops();
    EXPECT_EQ(g_stopped_a.load(), 4);
    EXPECT_EQ(g_stopped_b.load(), 1);
    // moving a registration keeps it
    EmergencyStop moved = std::move(a);
    EXPECT_FALSE(a.armed());
    EXPECT_TRUE(moved.armed());
    run_emergency_stops();
    EXPECT_EQ(g_stopped_a.load(), 6);
  }
  run_emergency_stops();
  EXPECT_EQ(g_stopped_a.load(), 6) << "released with its owner";
}

TEST(UsbEmergency, SlotsAreLimitedAndFreedAgain) {
  std::vector<EmergencyStop> held;
  for (std::size_t i = 0; i < EmergencyStop::kSlots; ++i) held.emplace_back(stop_b, nullptr);
  EXPECT_THROW(EmergencyStop(stop_b, nullptr), std::runtime_error);
  held.pop_back();
  EXPECT_NO_THROW(EmergencyStop(stop_b, nullptr));
}

}  // namespace
}  // namespace enact::devices::usb
