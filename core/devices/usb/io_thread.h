#pragma once
// The I/O thread of a USB backend: USB transfers block (a lock-step packet, a control
// transfer take about a millisecond), so they run on their own, non-real-time thread, and
// the real-time loop only exchanges values with it (Latest<T>, atomics): the ros2_control
// recipe for slow devices. The thread calls step(now_ns) on absolute deadlines of period_ns
// (on CLOCK_MONOTONIC); a step that takes longer than the period is followed at once by the
// next one. It ends when step returns false or stop() is called.
#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>

namespace enact::devices::usb {

class IoThread {
 public:
  IoThread() = default;
  ~IoThread() { stop(); }
  IoThread(const IoThread&) = delete;
  IoThread& operator=(const IoThread&) = delete;

  // start calling step every period_ns (> 0); a running thread is stopped first
  void start(std::int64_t period_ns, std::function<bool(std::int64_t now_ns)> step);
  // ask the thread to end after its current step, and join it (safe twice)
  void stop() noexcept;
  // whether the thread is still calling step
  bool running() const { return running_.load(); }
  // wait (polling, not real-time) until `counter` moved on from `before` (the thread did
  // what was asked), the thread ended, or timeout_ns passed
  void await(const std::atomic<std::uint64_t>& counter, std::uint64_t before, std::int64_t timeout_ns) const noexcept;

 private:
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> running_{false};
};

}  // namespace enact::devices::usb
