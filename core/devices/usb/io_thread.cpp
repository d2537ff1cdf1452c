#include "core/devices/usb/io_thread.h"

#include <algorithm>
#include <chrono>

#include "core/rt/clock.h"

namespace enact::devices::usb {

void IoThread::start(std::int64_t period_ns, std::function<bool(std::int64_t)> step) {
  stop();
  stop_.store(false);
  running_.store(true);
  thread_ = std::thread([this, period_ns, step = std::move(step)] {
    std::int64_t next = rt::now_ns();
    while (!stop_.load()) {
      const std::int64_t now = rt::now_ns();
      if (!step(now)) break;
      // the next deadline; a late step does not pile up missed ones
      next = std::max(next + period_ns, rt::now_ns() - period_ns);
      rt::sleep_until_ns(next);
    }
    running_.store(false);
  });
}

void IoThread::stop() noexcept {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
  running_.store(false);
}

void IoThread::await(const std::atomic<std::uint64_t>& counter, std::uint64_t before, std::int64_t timeout_ns) const noexcept {
  const std::int64_t give_up = rt::now_ns() + timeout_ns;
  while (counter.load() == before && running() && rt::now_ns() < give_up) std::this_thread::sleep_for(std::chrono::microseconds(200));
}

}  // namespace enact::devices::usb
