#pragma once
// One thread wakes another without blocking or allocating: a loop thread calls notify() (a
// write to an eventfd) when something it handed over must go on at once; the helper thread
// beside it waits in wait() with a deadline (its periodic round otherwise).
#include <cstdint>

namespace enact::rt {

class Wakeup {
 public:
  Wakeup();  // throws std::system_error when the kernel gives no eventfd
  ~Wakeup();
  Wakeup(const Wakeup&) = delete;
  Wakeup& operator=(const Wakeup&) = delete;

  // wakes the waiter (or its next wait); never blocks
  void notify() noexcept;
  // until notified or the monotonic clock reaches deadline_ns; true when notified
  bool wait(std::int64_t deadline_ns) noexcept;

 private:
  int fd_;
};

}  // namespace enact::rt
